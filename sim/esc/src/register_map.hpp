#pragma once
// The register file of an ET1100-class ESC as the master sees it
// (ESC datasheet section II): which bits of 0x0000-0x0F7F an ECAT write may
// change, and the values after power-on.
//
// Writability is a per-byte mask: an ECAT write stores
// (old & ~mask) | (new & mask) when the frame ends, so read-only and reserved
// bytes (mask 0) keep their value while the write still counts for the
// working counter, as on a real ESC. Registers whose write is a command
// rather than a value (error counters cleared by any write, the system time
// compared rather than stored, the receive-time latch) have mask 0 too; the
// unit that owns them reacts to the write instead.

#include <cstdint>

#include "ecpair/common/bytes.hpp"

namespace ecpair::sim::regs {

// Register space written through the shadow buffer (esc-facts.md §1).
inline constexpr std::uint16_t kShadowedEnd = 0x0F80;
// User RAM (no shadow), then process RAM.
inline constexpr std::uint16_t kUserRam = 0x0F80;
inline constexpr std::uint16_t kProcessRam = 0x1000;
inline constexpr std::uint32_t kAddressSpace = 0x10000;

// Whether the address ranges [begin, end) and [other_begin, other_end) share a byte.
inline bool overlaps(std::uint32_t begin, std::uint32_t end, std::uint32_t other_begin, std::uint32_t other_end) {
    return begin < other_end && other_begin < end;
}

// Registers the simulator uses beyond wire/esc_registers.hpp.
inline constexpr std::uint16_t kDlControlFlags = 0x0100;
inline constexpr std::uint16_t kDlControlAlias = 0x0103;
inline constexpr std::uint16_t kRwOffset = 0x0108;
inline constexpr std::uint16_t kEscConfig = 0x0141;  // b0 device emulation (from SII word 0)
inline constexpr std::uint16_t kPdiConfig = 0x0150;
inline constexpr std::uint16_t kPdiConfigExtended = 0x0152;
inline constexpr std::uint16_t kEscConfigA5 = 0x0142;
inline constexpr std::uint16_t kEscConfigA6 = 0x0144;
inline constexpr std::uint16_t kAlEventMask = 0x0204;
inline constexpr std::uint16_t kEpuErrorCounter = 0x030C;
inline constexpr std::uint16_t kPdiErrorCounter = 0x030D;
inline constexpr std::uint16_t kWatchdogTimePdi = 0x0410;
inline constexpr std::uint16_t kWatchdogTimeProcessData = 0x0420;
inline constexpr std::uint16_t kWatchdogStatusProcessData = 0x0440;
inline constexpr std::uint16_t kWatchdogCounterProcessData = 0x0442;
inline constexpr std::uint16_t kWatchdogCounterPdi = 0x0443;
inline constexpr std::uint16_t kDcSpeedCounterDiff = 0x0932;
inline constexpr std::uint16_t kDcTimeDifferenceFilterDepth = 0x0934;
inline constexpr std::uint16_t kDcSpeedCounterFilterDepth = 0x0935;
inline constexpr std::uint16_t kDcActivationStatus = 0x0984;
inline constexpr std::uint16_t kDcSync0Status = 0x098E;
inline constexpr std::uint16_t kDcSync1Status = 0x098F;
inline constexpr std::uint16_t kDcNextSync1 = 0x0998;
inline constexpr std::uint16_t kDcSyncPulseLength = 0x0982;

inline constexpr int kFmmuCount = 8;
inline constexpr int kSmCount = 8;

// ECAT event request (0x0210) bits.
inline constexpr std::uint16_t kEventDlStatus = 0x0004;
inline constexpr std::uint16_t kEventAlStatus = 0x0008;
inline constexpr int kEventFirstSmBit = 4;

// The bits of a register byte an ECAT write may change (0 for >= 0x0F80).
std::uint8_t ecat_write_mask(std::uint16_t address);

// What differs between ESCs built from different descriptions.
struct EscHardware {
    std::uint8_t ram_kib = 8;
    std::uint8_t port_descriptor = 0x0F;
    bool dc = true;        // distributed clocks (0x0008 b2, with enhanced SYNC activation b8)
    bool dc_64bit = true;  // 64-bit system time (0x0008 b3)
};

// Power-on values of 0x0000-0x0FFF (the part not loaded from the SII).
// `registers` spans at least 0x1000 bytes and is overwritten.
void write_reset_values(Bytes registers, const EscHardware& hardware);

}  // namespace ecpair::sim::regs
