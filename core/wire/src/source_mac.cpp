#include "ecpair/wire/source_mac.hpp"

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"

namespace ecpair::wire {

std::uint8_t SourceMac::byte0() const {
    std::uint8_t b = static_cast<std::uint8_t>((retry_index & 0x07) << 4);
    if (redundancy) b |= kRedundancyBit;
    if (forwarded_main) b |= kForwardedMainBit;
    if (forwarded_red) b |= kForwardedRedBit;
    if (slave_forwarded) b |= kSlaveForwardedBit;
    if (group_bit) b |= kGroupBit;
    return b;
}

MacAddress SourceMac::encode() const {
    return {{byte0(), frame_id, reserved, nic.bytes[0], nic.bytes[1], nic.bytes[2]}};
}

SourceMac SourceMac::decode(const MacAddress& mac) {
    const std::uint8_t b = mac.bytes[0];
    SourceMac s;
    s.retry_index = static_cast<std::uint8_t>((b & kRetryMask) >> 4);
    s.redundancy = (b & kRedundancyBit) != 0;
    s.forwarded_main = (b & kForwardedMainBit) != 0;
    s.forwarded_red = (b & kForwardedRedBit) != 0;
    s.slave_forwarded = (b & kSlaveForwardedBit) != 0;
    s.group_bit = (b & kGroupBit) != 0;
    s.frame_id = mac.bytes[1];
    s.reserved = mac.bytes[2];
    s.nic = NicBytes::of(mac);
    return s;
}

std::string SourceMac::to_string() const {
    return fmt::format("byte0=0x{:02x} retry={}{}{}{}{} id=0x{:02x} nic={}", byte0(), retry_index,
                       redundancy ? " red" : "", forwarded_main ? " fwd-main" : "",
                       forwarded_red ? " fwd-red" : "", slave_forwarded ? " slave-fwd" : "", frame_id,
                       to_hex(nic.bytes));
}

}  // namespace ecpair::wire
