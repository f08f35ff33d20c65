#pragma once
// Hex text <-> bytes, as used by ENI hexBinary fields, logs and tests.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair {

// "0a1B" -> {0x0a, 0x1b}. Whitespace is ignored; anything else that is not a
// hex digit, or an odd digit count, gives nullopt.
std::optional<std::vector<std::uint8_t>> parse_hex(std::string_view text);

// {0x0a, 0x1b} -> "0a1b" (lower case, optional separator between bytes).
std::string to_hex(ConstBytes bytes, std::string_view separator = {});

}  // namespace ecpair
