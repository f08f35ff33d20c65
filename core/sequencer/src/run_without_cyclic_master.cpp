#include "ecpair/sequencer/run_without_cyclic_master.hpp"

#include <atomic>

namespace ecpair::sequencer {

MasterState run_without_cyclic_master(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus,
                                      MasterState target, std::chrono::milliseconds timeout) {
    std::atomic<eni::SlaveState> cyclic{eni::SlaveState::Init};
    StateMachineHooks hooks;
    hooks.request_cyclic_state = [&cyclic](eni::SlaveState state) { cyclic = state; };
    hooks.cyclic_state = [&cyclic] { return cyclic.load(); };
    MasterStateMachine machine(std::move(eni), bus, hooks);
    machine.request(target);
    machine.wait_idle(timeout);
    return machine.current();
}

}  // namespace ecpair::sequencer
