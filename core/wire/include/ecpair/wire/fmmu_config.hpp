#pragma once
// FMMU (16 bytes at 0x0600 + 16n) and SyncManager (8 bytes at 0x0800 + 8n)
// configuration records, as masters write them and ESCs hold them
// (esc-facts.md §2).

#include <cstdint>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

struct FmmuConfig {
    static constexpr std::size_t kSize = 16;

    std::uint32_t logical_start = 0;
    std::uint16_t length = 0;  // bytes of the logical range (first to last byte touched)
    std::uint8_t logical_start_bit = 0;
    std::uint8_t logical_stop_bit = 7;
    std::uint16_t physical_start = 0;
    std::uint8_t physical_start_bit = 0;
    bool read = false;   // type bit 0: LRD/LRW read slave memory
    bool write = false;  // type bit 1: LWR/LRW write slave memory
    bool active = false;

    // Whether the logical byte range overlaps [address, address + size).
    bool overlaps(std::uint32_t address, std::size_t size) const;

    void encode(Bytes out) const;  // out.size() >= kSize
    static FmmuConfig decode(ConstBytes in);
    friend bool operator==(const FmmuConfig&, const FmmuConfig&) = default;
};

struct SyncManagerConfig {
    static constexpr std::size_t kSize = 8;

    std::uint16_t physical_start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;  // [1:0] mode (00 buffered, 10 mailbox), [3:2] direction (00 read, 01 write)
    std::uint8_t status = 0;
    std::uint8_t activate = 0;  // b0 enable
    std::uint8_t pdi_control = 0;

    bool enabled() const { return (activate & 0x01) != 0; }
    bool mailbox() const { return (control & 0x03) == 0x02; }
    bool master_writes() const { return (control & 0x0C) == 0x04; }

    void encode(Bytes out) const;
    static SyncManagerConfig decode(ConstBytes in);
    friend bool operator==(const SyncManagerConfig&, const SyncManagerConfig&) = default;
};

}  // namespace ecpair::wire
