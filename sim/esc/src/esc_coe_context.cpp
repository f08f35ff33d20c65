// AlState and eni::SlaveState share the AL status values (1, 2, 3, 4, 8).

#include "esc_coe_context.hpp"

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {

EscCoeContext::EscCoeContext(const EscMemory& memory, const AlStateMachine& al, EscLayout& layout,
                             std::shared_ptr<spdlog::logger> log, std::string owner)
    : memory_(memory), al_(al), layout_(layout), log_(std::move(log)), owner_(std::move(owner)) {}

std::uint16_t EscCoeContext::station_address() const { return memory_.load<std::uint16_t>(wire::reg::kStationAddress); }

eni::SlaveState EscCoeContext::al_state() const { return static_cast<eni::SlaveState>(al_.state()); }

void EscCoeContext::process_data_size_changed(std::uint8_t sm, std::optional<std::uint16_t> bytes) {
    if (sm >= EscLayout::kSmCount) return;
    SmPlan& plan = layout_.sms[sm];
    if ((plan.role != SmRole::Outputs && plan.role != SmRole::Inputs) || plan.expected_size == bytes) return;
    if (bytes) {
        log_->debug("{}: PDO assignment over CoE: SM{} now expects {} bytes", owner_, sm, *bytes);
    } else {
        log_->debug("{}: PDO assignment over CoE names a PDO the slave does not describe: SM{} accepts any length",
                   owner_, sm);
    }
    plan.expected_size = bytes;
}

}  // namespace ecpair::sim
