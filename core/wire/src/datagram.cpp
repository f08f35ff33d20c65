#include "ecpair/wire/datagram.hpp"

namespace ecpair::wire {

void DatagramHeader::encode(Bytes out) const {
    out[0] = static_cast<std::uint8_t>(command);
    out[1] = index;
    store_le<std::uint32_t>(out, 2, address);
    std::uint16_t word = static_cast<std::uint16_t>(length & kLengthMask);
    word = static_cast<std::uint16_t>(word | ((reserved & 0x7u) << 11));
    if (circulating) word |= kCirculatingBit;
    if (more) word |= kMoreBit;
    store_le<std::uint16_t>(out, 6, word);
    store_le<std::uint16_t>(out, 8, irq);
}

DatagramHeader DatagramHeader::decode(ConstBytes in) {
    DatagramHeader h;
    h.command = static_cast<Command>(in[0]);
    h.index = in[1];
    h.address = load_le<std::uint32_t>(in, 2);
    const auto word = load_le<std::uint16_t>(in, 6);
    h.length = static_cast<std::uint16_t>(word & kLengthMask);
    h.reserved = static_cast<std::uint8_t>((word & kReservedMask) >> 11);
    h.circulating = (word & kCirculatingBit) != 0;
    h.more = (word & kMoreBit) != 0;
    h.irq = load_le<std::uint16_t>(in, 8);
    return h;
}

}  // namespace ecpair::wire
