// The write masks are one table built at compile time from the register
// list below (datasheet section II, ET1100 column). Everything not listed is
// reserved or read-only for ECAT. The reset values follow the same sheet;
// the values an ESC loads from its SII configuration area (PDI control,
// alias, ...) are written by the SII unit afterwards.

#include "register_map.hpp"

#include <algorithm>
#include <array>
#include <cassert>

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim::regs {
namespace {

namespace reg = wire::reg;

struct Writable {
    std::uint16_t address;
    std::uint16_t count;  // bytes
    std::uint8_t mask;
};

// ECAT-writable register bytes. Bytes whose write is an action (counters
// cleared by any write, the DC system time and receive-time latch) are
// deliberately absent: their owners react to the staged write.
constexpr std::array kWritable = {
    Writable{reg::kStationAddress, 2, 0xFF},
    Writable{kDlControlFlags, 1, 0x03},          // forwarding rule, temporary loop
    Writable{reg::kDlControlLoop, 1, 0xFF},      // loop setting of ports 0-3
    Writable{0x0102, 1, 0x07},                   // RX FIFO size
    Writable{kDlControlAlias, 1, 0x01},          // station alias enable
    Writable{kRwOffset, 2, 0xFF},
    Writable{reg::kAlControl, 1, 0x3F},          // state, error ack, ID request
    Writable{reg::kAlControl + 1, 1, 0xFF},      // application specific
    Writable{0x0138, 2, 0xFF},                   // RUN/ERR LED override
    Writable{reg::kEcatEventMask, 2, 0xFF},
    Writable{reg::kWatchdogDivider, 2, 0xFF},
    Writable{kWatchdogTimePdi, 2, 0xFF},
    Writable{kWatchdogTimeProcessData, 2, 0xFF},
    Writable{reg::kSiiConfig, 1, 0x03},          // PDI access, force ECAT access
    Writable{reg::kSiiControl, 1, 0x01},         // write enable
    Writable{reg::kSiiControl + 1, 1, 0x07},     // command
    Writable{reg::kSiiAddress, 4, 0xFF},
    Writable{reg::kSiiData, 8, 0xFF},
    Writable{reg::kDcSystemTimeOffset, 8, 0xFF},
    Writable{reg::kDcSystemTimeDelay, 4, 0xFF},
    Writable{reg::kDcSpeedCounterStart, 1, 0xFF},
    Writable{reg::kDcSpeedCounterStart + 1, 1, 0x7F},  // bit 15 reserved
    Writable{kDcTimeDifferenceFilterDepth, 1, 0x0F},
    Writable{kDcSpeedCounterFilterDepth, 1, 0x0F},
    Writable{reg::kDcCycleUnitControl, 1, 0x31},
    Writable{reg::kDcActivation, 1, 0xFF},
    Writable{reg::kDcStartTime, 8, 0xFF},
    Writable{reg::kDcCycleTime0, 8, 0xFF},       // SYNC0 and SYNC1 cycle times
    Writable{0x09A8, 2, 0xFF},                   // latch control
    Writable{0x0F00, 4, 0xFF},                   // digital outputs
    Writable{0x0F10, 8, 0xFF},                   // general purpose outputs
};

// FMMU n: logical start(4) length(2) start bit stop bit physical start(2)
// physical start bit, type, activate, 3 reserved bytes.
constexpr std::array<std::uint8_t, reg::kFmmuSize> kFmmuMasks = {
    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x07, 0x07, 0xFF, 0xFF, 0x07, 0x03, 0x01, 0x00, 0x00, 0x00};

// SM n: physical start(2) length(2) control, status (r/-), activate (enable,
// repeat request, latch events), PDI control (r/-).
constexpr std::array<std::uint8_t, reg::kSmSize> kSmMasks = {0xFF, 0xFF, 0xFF, 0xFF, 0x7F, 0x00, 0xC3, 0x00};

constexpr std::array<std::uint8_t, kShadowedEnd> build_masks() {
    std::array<std::uint8_t, kShadowedEnd> masks{};
    for (const auto& w : kWritable) {
        for (std::uint16_t i = 0; i < w.count; ++i) masks[w.address + i] = w.mask;
    }
    for (int f = 0; f < kFmmuCount; ++f) {
        for (std::size_t i = 0; i < kFmmuMasks.size(); ++i) {
            masks[reg::kFmmuBase + static_cast<std::size_t>(f) * reg::kFmmuSize + i] = kFmmuMasks[i];
        }
    }
    for (int s = 0; s < kSmCount; ++s) {
        for (std::size_t i = 0; i < kSmMasks.size(); ++i) {
            masks[reg::kSmBase + static_cast<std::size_t>(s) * reg::kSmSize + i] = kSmMasks[i];
        }
    }
    return masks;
}

constexpr auto kMasks = build_masks();

}  // namespace

std::uint8_t ecat_write_mask(std::uint16_t address) {
    return address < kShadowedEnd ? kMasks[address] : std::uint8_t{0};
}

void write_reset_values(Bytes registers, const EscHardware& hardware) {
    assert(registers.size() >= kProcessRam);
    std::fill_n(registers.begin(), kProcessRam, std::uint8_t{0});
    registers[reg::kType] = 0x11;  // ET1100
    registers[reg::kRevision] = 0x00;
    store_le<std::uint16_t>(registers, reg::kBuild, 0x0003);
    registers[reg::kFmmuCount] = kFmmuCount;
    registers[reg::kSmCount] = kSmCount;
    registers[reg::kRamSize] = hardware.ram_kib;
    registers[reg::kPortDescriptor] = hardware.port_descriptor;
    // Features: bit-wise FMMUs (b0 = 0), DC (b2), 64-bit DC (b3), low-jitter
    // EBUS (b4), enhanced link detection EBUS/MII (b5, b6), separate FCS
    // error handling (b7), enhanced DC SYNC activation (b8); LRW and
    // APRW/FPRW/BRW supported (b9, b10 = 0). An ESC without DC has neither
    // DC bit nor the enhanced activation; a 32-bit DC lacks b3.
    std::uint16_t features = 0x00F0;
    if (hardware.dc) features = static_cast<std::uint16_t>(features | 0x0104U | (hardware.dc_64bit ? 0x0008U : 0U));
    store_le<std::uint16_t>(registers, reg::kFeatures, features);
    registers[kDlControlFlags] = 0x01;  // forwarding rule: destroy non-EtherCAT frames
    registers[0x0102] = 0x07;           // RX FIFO size: default
    store_le<std::uint16_t>(registers, reg::kAlControl, 0x0001);
    store_le<std::uint16_t>(registers, reg::kAlStatus, 0x0001);
    store_le<std::uint32_t>(registers, kAlEventMask, 0x00FFFF0F);
    store_le<std::uint16_t>(registers, reg::kWatchdogDivider, 0x09C2);  // 100 us
    store_le<std::uint16_t>(registers, kWatchdogTimePdi, 0x03E8);       // 100 ms
    store_le<std::uint16_t>(registers, kWatchdogTimeProcessData, 0x03E8);
    store_le<std::uint16_t>(registers, reg::kDcSpeedCounterStart, 0x1000);
    registers[kDcTimeDifferenceFilterDepth] = 0x04;
    registers[kDcSpeedCounterFilterDepth] = 0x0C;
}

}  // namespace ecpair::sim::regs
