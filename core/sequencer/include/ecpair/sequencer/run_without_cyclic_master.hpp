#pragma once
// The state machine driven over a bus that has no cyclic master behind it:
// for tests and benchmarks that bring a simulated segment to a state with
// acyclic frames only. The cyclic frames' state the machine asks for is only
// remembered (and reported back), so no transition waits for a cycle.

#include <chrono>
#include <memory>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"

namespace ecpair::sequencer {

// Requests `target` and waits up to `timeout`; returns the state reached.
MasterState run_without_cyclic_master(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus,
                                      MasterState target, std::chrono::milliseconds timeout);

}  // namespace ecpair::sequencer
