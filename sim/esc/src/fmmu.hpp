#pragma once
// The FMMUs (datasheet I §7): logical addressing for LRD/LWR/LRW.
//
// Each active FMMU maps a run of logical bits (from the start bit of its first
// logical byte to the stop bit of its last) onto as many physical bits from
// its physical start bit. A logical read copies the mapped memory bits into
// the datagram and leaves unmapped bits untouched, i.e. data = (memory & mask)
// | (data & ~mask); a logical write stores the mapped datagram bits. Only
// FMMUs of the matching type take part (b0 read, b1 write). If two FMMUs of
// the same direction map the same logical byte, the lower-numbered one wins.
//
// Byte-aligned mappings (start bit 0, stop bit 7, physical start bit 0) that
// no lower FMMU overlaps take a copy fast path; everything else goes bit by
// bit. Physical accesses go through PhysicalAccess, so SyncManagers still
// decide, and a refused byte does not count.

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecpair/common/bytes.hpp"
#include "esc_memory.hpp"
#include "physical_access.hpp"

namespace ecpair::sim {

class FmmuUnit {
public:
    // Re-decodes the FMMU registers (0x0600 + 16n).
    void refresh(const EscMemory& memory);
    void reset() { mappings_ = {}; count_ = 0; }

    // LRD and the read half of LRW. True when any mapped bit was read.
    bool read(std::uint32_t logical_address, Bytes data, PhysicalAccess& memory) const;
    // LWR and the write half of LRW: `source` holds the datagram data as it
    // arrived. True when any mapped bit was written.
    bool write(std::uint32_t logical_address, ConstBytes source, PhysicalAccess& memory) const;

    // The part [begin, end) of a datagram at `logical_address` that the write
    // FMMUs cover (the hull of their overlaps; empty when none does).
    struct Window {
        std::size_t begin = 0;
        std::size_t end = 0;
    };
    Window write_window(std::uint32_t logical_address, std::size_t length) const;

    // Whether an active FMMU maps a logical byte of [logical_address, + length).
    bool maps(std::uint32_t logical_address, std::size_t length) const;
    // The active FMMUs in FMMU order, and the logical bytes [begin, end) each maps.
    struct LogicalBytes {
        std::uint64_t begin = 0;
        std::uint64_t end = 0;
    };
    std::size_t active_count() const { return count_; }
    // Whether an active FMMU maps physical memory below `address` (registers, for 0x1000).
    bool maps_physical_below(std::uint32_t address) const {
        for (std::size_t i = 0; i < count_; ++i) {
            if (mappings_[i].physical_bit_begin / 8 < address) return true;
        }
        return false;
    }
    LogicalBytes logical_bytes(std::size_t active) const {
        return {mappings_[active].logical_byte_begin, mappings_[active].logical_byte_end};
    }

private:
    struct Mapping {
        std::uint64_t logical_bit_begin = 0;  // absolute bit numbers
        std::uint64_t logical_bit_end = 0;
        std::uint32_t physical_bit_begin = 0;
        std::uint32_t logical_byte_begin = 0;  // bytes touched, [begin, end)
        std::uint64_t logical_byte_end = 0;
        bool reads = false;
        bool writes = false;
        bool byte_aligned = false;
        bool shadowed_read = false;   // a lower read FMMU shares a logical byte
        bool shadowed_write = false;  // a lower write FMMU shares a logical byte
    };

    bool claimed_by_lower(std::size_t index, std::uint64_t logical_byte, bool for_write) const;
    bool read_bits(std::size_t index, std::uint32_t logical_address, Bytes data, PhysicalAccess& memory) const;
    bool write_bits(std::size_t index, std::uint32_t logical_address, ConstBytes source, PhysicalAccess& memory) const;

    std::array<Mapping, regs::kFmmuCount> mappings_{};
    std::size_t count_ = 0;  // active mappings, in FMMU order
};

}  // namespace ecpair::sim
