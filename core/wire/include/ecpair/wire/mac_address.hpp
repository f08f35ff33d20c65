#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ecpair::wire {

struct MacAddress {
    std::array<std::uint8_t, 6> bytes{};

    static constexpr MacAddress broadcast() { return {{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}}; }

    // Accepts "aa:bb:cc:dd:ee:ff", "aa-bb-..." and the ENI form "aabbccddeeff".
    static std::optional<MacAddress> parse(std::string_view text);
    std::string to_string() const;  // "aa:bb:cc:dd:ee:ff"

    bool is_group() const { return (bytes[0] & 0x01) != 0; }
    friend bool operator==(const MacAddress&, const MacAddress&) = default;
};

}  // namespace ecpair::wire
