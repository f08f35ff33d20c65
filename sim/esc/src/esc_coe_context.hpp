#pragma once
// The mailbox's and the CoE server's view of the ESC it runs in
// (CoeSlaveContext, a MailboxSlave): the station address register, the AL
// state, and the expected sizes of the process data SyncManagers. The
// slave stack's SAFEOP check reads those sizes from the layout
// (slave_stack_checks), so a PDO assignment written over CoE changes what
// the check expects, as on a real slave. Only SyncManagers the layout plans
// as Outputs/Inputs take a new size.

#include <memory>
#include <string>

#include <spdlog/logger.h>

#include "al_state_machine.hpp"
#include "ecpair/sim/coe_server.hpp"
#include "esc_layout.hpp"
#include "esc_memory.hpp"

namespace ecpair::sim {

class EscCoeContext final : public CoeSlaveContext {
public:
    EscCoeContext(const EscMemory& memory, const AlStateMachine& al, EscLayout& layout,
                  std::shared_ptr<spdlog::logger> log, std::string owner);

    std::uint16_t station_address() const override;
    eni::SlaveState al_state() const override;
    void process_data_size_changed(std::uint8_t sm, std::optional<std::uint16_t> bytes) override;

private:
    const EscMemory& memory_;
    const AlStateMachine& al_;
    EscLayout& layout_;
    std::shared_ptr<spdlog::logger> log_;
    std::string owner_;
};

}  // namespace ecpair::sim
