#include "ecpair/tap_bridge/interface_address.hpp"

#include <arpa/inet.h>

#include <charconv>

#include <fmt/format.h>

namespace ecpair::tap_bridge {

Expected<InterfaceAddress, std::string> InterfaceAddress::parse(std::string_view text) {
    InterfaceAddress a;
    const auto slash = text.find('/');
    const std::string host(text.substr(0, slash));
    if (inet_pton(AF_INET, host.c_str(), a.bytes.data()) == 1) {
        a.family = Family::Ipv4;
        a.prefix_length = 32;
    } else if (inet_pton(AF_INET6, host.c_str(), a.bytes.data()) == 1) {
        a.family = Family::Ipv6;
        a.prefix_length = 128;
    } else {
        return unexpected(fmt::format("'{}': '{}' is no IPv4 or IPv6 address", text, host));
    }
    if (slash != std::string_view::npos) {
        const auto digits = text.substr(slash + 1);
        unsigned value = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        const unsigned max = a.family == Family::Ipv4 ? 32 : 128;
        if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size() || value > max) {
            return unexpected(fmt::format("'{}': prefix length must be 0..{}", text, max));
        }
        a.prefix_length = static_cast<std::uint8_t>(value);
    }
    return a;
}

std::string InterfaceAddress::to_string() const {
    char text[INET6_ADDRSTRLEN] = {};
    inet_ntop(family == Family::Ipv4 ? AF_INET : AF_INET6, bytes.data(), text, sizeof text);
    return fmt::format("{}/{}", text, prefix_length);
}

}  // namespace ecpair::tap_bridge
