// Saturating counters and their clear-by-write groups.

#include "error_counters.hpp"

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim::error_counters {
namespace {

namespace reg = wire::reg;

constexpr std::uint16_t kForwardedRxErrorCounters = 0x0308;
constexpr std::uint16_t kRxCountersEnd = 0x030C;
constexpr std::uint16_t kLostLinkCountersEnd = 0x0314;

void saturating_increment(EscMemory& memory, std::uint16_t address) {
    const auto value = memory.u8(address);
    if (value < 0xFF) memory.set_u8(address, static_cast<std::uint8_t>(value + 1));
}

void clear_if_written(EscMemory& memory, std::uint16_t begin, std::uint16_t end) {
    if (!memory.staged_any(begin, end)) return;
    for (std::uint16_t a = begin; a < end; ++a) memory.set_u8(a, 0);
}

}  // namespace

void count_processing_unit_error(EscMemory& memory) { saturating_increment(memory, regs::kEpuErrorCounter); }

void count_lost_link(EscMemory& memory, int port) {
    saturating_increment(memory, static_cast<std::uint16_t>(reg::kLostLinkCounters + port));
}

void count_received_error(EscMemory& memory, int port, bool marked_upstream) {
    if (marked_upstream) {
        saturating_increment(memory, static_cast<std::uint16_t>(kForwardedRxErrorCounters + port));
        return;
    }
    const auto invalid_frames = static_cast<std::uint16_t>(reg::kRxErrorCounters + 2 * port);
    saturating_increment(memory, invalid_frames);
    saturating_increment(memory, static_cast<std::uint16_t>(invalid_frames + 1));
}

void apply_clearing_writes(EscMemory& memory) {
    clear_if_written(memory, reg::kRxErrorCounters, kRxCountersEnd);
    clear_if_written(memory, regs::kEpuErrorCounter, regs::kEpuErrorCounter + 1);
    clear_if_written(memory, regs::kPdiErrorCounter, regs::kPdiErrorCounter + 1);
    clear_if_written(memory, reg::kLostLinkCounters, kLostLinkCountersEnd);
    clear_if_written(memory, regs::kWatchdogCounterProcessData, regs::kWatchdogCounterProcessData + 1);
    clear_if_written(memory, regs::kWatchdogCounterPdi, regs::kWatchdogCounterPdi + 1);
}

}  // namespace ecpair::sim::error_counters
