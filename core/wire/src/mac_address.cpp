#include "ecpair/wire/mac_address.hpp"

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"

namespace ecpair::wire {

std::optional<MacAddress> MacAddress::parse(std::string_view text) {
    std::string digits;
    digits.reserve(12);
    for (const char c : text) {
        if (c == ':' || c == '-') continue;
        digits.push_back(c);
    }
    if (digits.size() != 12) return std::nullopt;
    const auto bytes = parse_hex(digits);
    if (!bytes || bytes->size() != 6) return std::nullopt;
    MacAddress mac;
    std::copy(bytes->begin(), bytes->end(), mac.bytes.begin());
    return mac;
}

std::string MacAddress::to_string() const {
    return to_hex(bytes, ":");
}

}  // namespace ecpair::wire
