// The divider and the time are read at each trigger, so a master that
// rewrites them (the ENIs' "set watchdog divider" / "set SM watchdog"
// InitCmds) changes the next period.

#include "process_data_watchdog.hpp"

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

constexpr std::uint64_t kBaseTickNs = 40;  // 25 MHz
constexpr std::uint16_t kStatusRunning = 0x0001;

}  // namespace

ProcessDataWatchdog::ProcessDataWatchdog(EscMemory& memory) : memory_(memory) {}

void ProcessDataWatchdog::reset() {
    deadline_ns_.reset();
    write_status();
}

std::uint64_t ProcessDataWatchdog::period_ns() const {
    const std::uint64_t divider = memory_.load<std::uint16_t>(wire::reg::kWatchdogDivider);
    const std::uint64_t ticks = memory_.load<std::uint16_t>(regs::kWatchdogTimeProcessData);
    return (divider + 2) * kBaseTickNs * ticks;
}

void ProcessDataWatchdog::trigger(std::uint64_t now_ns) {
    const std::uint64_t period = period_ns();
    if (period == 0) {
        deadline_ns_.reset();  // disabled
    } else {
        deadline_ns_ = now_ns + period;
    }
    write_status();
}

bool ProcessDataWatchdog::advance(std::uint64_t now_ns) {
    if (!deadline_ns_ || now_ns < *deadline_ns_) return false;
    deadline_ns_.reset();
    const auto count = memory_.u8(regs::kWatchdogCounterProcessData);
    if (count < 0xFF) memory_.set_u8(regs::kWatchdogCounterProcessData, static_cast<std::uint8_t>(count + 1));
    write_status();
    return true;
}

void ProcessDataWatchdog::write_status() {
    const bool disabled = memory_.load<std::uint16_t>(regs::kWatchdogTimeProcessData) == 0;
    memory_.store<std::uint16_t>(regs::kWatchdogStatusProcessData,
                                 deadline_ns_ || disabled ? kStatusRunning : std::uint16_t{0});
}

}  // namespace ecpair::sim
