#pragma once
// An address for the TAP device as an operator writes it: "10.77.0.1/24"
// or "fd00:77::1/64" (the prefix length may be left out: /32 and /128).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "ecpair/common/expected.hpp"

namespace ecpair::tap_bridge {

struct InterfaceAddress {
    enum class Family : std::uint8_t { Ipv4, Ipv6 };
    Family family = Family::Ipv4;
    std::array<std::uint8_t, 16> bytes{};  // network order; IPv4 uses the first 4
    std::uint8_t prefix_length = 32;

    // Errors say what is wrong: "'10.77.0.1/33': prefix length must be 0..32".
    static Expected<InterfaceAddress, std::string> parse(std::string_view text);
    std::string to_string() const;
};

}  // namespace ecpair::tap_bridge
