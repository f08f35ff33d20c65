#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::wire {

bool FmmuConfig::overlaps(std::uint32_t address, std::size_t size) const {
    if (length == 0 || size == 0) return false;
    const std::uint64_t begin = logical_start;
    const std::uint64_t end = begin + length;
    const std::uint64_t other_begin = address;
    const std::uint64_t other_end = other_begin + size;
    return begin < other_end && other_begin < end;
}

void FmmuConfig::encode(Bytes out) const {
    store_le<std::uint32_t>(out, 0, logical_start);
    store_le<std::uint16_t>(out, 4, length);
    out[6] = logical_start_bit;
    out[7] = logical_stop_bit;
    store_le<std::uint16_t>(out, 8, physical_start);
    out[10] = physical_start_bit;
    out[11] = static_cast<std::uint8_t>((read ? 0x01 : 0x00) | (write ? 0x02 : 0x00));
    out[12] = active ? 0x01 : 0x00;
    out[13] = 0;
    out[14] = 0;
    out[15] = 0;
}

FmmuConfig FmmuConfig::decode(ConstBytes in) {
    FmmuConfig f;
    f.logical_start = load_le<std::uint32_t>(in, 0);
    f.length = load_le<std::uint16_t>(in, 4);
    f.logical_start_bit = static_cast<std::uint8_t>(in[6] & 0x07);
    f.logical_stop_bit = static_cast<std::uint8_t>(in[7] & 0x07);
    f.physical_start = load_le<std::uint16_t>(in, 8);
    f.physical_start_bit = static_cast<std::uint8_t>(in[10] & 0x07);
    f.read = (in[11] & 0x01) != 0;
    f.write = (in[11] & 0x02) != 0;
    f.active = (in[12] & 0x01) != 0;
    return f;
}

void SyncManagerConfig::encode(Bytes out) const {
    store_le<std::uint16_t>(out, 0, physical_start);
    store_le<std::uint16_t>(out, 2, length);
    out[4] = control;
    out[5] = status;
    out[6] = activate;
    out[7] = pdi_control;
}

SyncManagerConfig SyncManagerConfig::decode(ConstBytes in) {
    SyncManagerConfig s;
    s.physical_start = load_le<std::uint16_t>(in, 0);
    s.length = load_le<std::uint16_t>(in, 2);
    s.control = in[4];
    s.status = in[5];
    s.activate = in[6];
    s.pdi_control = in[7];
    return s;
}

}  // namespace ecpair::wire
