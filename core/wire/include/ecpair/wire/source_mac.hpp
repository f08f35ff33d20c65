#pragma once
// The state a master carries in the source MAC of every frame it sends or
// forwards (design.md §2):
//
//   byte 0: 0x70 retry index (acyclic frames, 0..7)
//           0x08 redundancy bit (sent on RED)
//           0x80 forwarded by the INACTIVE out of its RED
//           0x04 forwarded by the INACTIVE out of its MAIN
//           0x02 slave forwarding (set by an ESC whose forwarding rule is on)
//           0x01 must stay 0 (the Ethernet group bit)
//   byte 1: redundancy frame id, counted per frame per NIC
//   byte 2: reserved
//   bytes 3-5: the sending master NIC's own bytes

#include <array>
#include <cstdint>
#include <string>

#include "ecpair/wire/mac_address.hpp"

namespace ecpair::wire {

struct NicBytes {
    std::array<std::uint8_t, 3> bytes{};
    static NicBytes of(const MacAddress& mac) { return {{mac.bytes[3], mac.bytes[4], mac.bytes[5]}}; }
    friend bool operator==(const NicBytes&, const NicBytes&) = default;
};

struct SourceMac {
    static constexpr std::uint8_t kRetryMask = 0x70;
    static constexpr std::uint8_t kRedundancyBit = 0x08;
    static constexpr std::uint8_t kForwardedRedBit = 0x80;
    static constexpr std::uint8_t kForwardedMainBit = 0x04;
    static constexpr std::uint8_t kSlaveForwardedBit = 0x02;
    static constexpr std::uint8_t kGroupBit = 0x01;

    std::uint8_t retry_index = 0;  // 0..7; encode() keeps the low 3 bits
    bool redundancy = false;
    bool forwarded_main = false;
    bool forwarded_red = false;
    bool slave_forwarded = false;
    bool group_bit = false;  // kept so that decode/encode round-trips any MAC
    std::uint8_t frame_id = 0;
    std::uint8_t reserved = 0;
    NicBytes nic{};

    std::uint8_t byte0() const;
    MacAddress encode() const;
    static SourceMac decode(const MacAddress& mac);
    std::string to_string() const;  // for logs: "retry=0 red fwdM id=0x12 nic=aabbcc"

    friend bool operator==(const SourceMac&, const SourceMac&) = default;
};

}  // namespace ecpair::wire
