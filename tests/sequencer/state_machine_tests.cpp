// MasterStateMachine against a scripted bus: a master that is INACTIVE
// (the bus refuses everything) stops quietly, and a request for the state
// it is in does nothing.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"
#include "fakes.hpp"

namespace ecpair::test {
namespace {

using sequencer::MasterState;
using sequencer::SequenceFailure;

std::shared_ptr<const eni::EniConfig> cherry() {
    auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/twincat_cherryecat_cia402_1slave.xml"));
    REQUIRE(loaded);
    return *loaded;
}

TEST_CASE("An INACTIVE master stops the sequence at the first refusal, without an error storm", "[sequencer][sm]") {
    ScriptedBus bus([](const bus::DatagramRequest&) { return bus_error(bus::BusErrc::MasterRedStateInactive); });
    VirtualClock clock;
    master::EventQueue events;
    std::optional<sequencer::SequenceResult> done;
    std::mutex done_mutex;
    sequencer::StateMachineHooks hooks;
    hooks.on_done = [&](const sequencer::SequenceResult& r) {
        std::lock_guard lock(done_mutex);
        done = r;
    };
    sequencer::MasterStateMachine machine(cherry(), bus, hooks, &events, clock);
    machine.request(MasterState::Op);
    REQUIRE(machine.wait_idle(std::chrono::seconds(10)));

    CHECK(machine.current() == MasterState::Init);
    CHECK(machine.target() == MasterState::Op);
    const auto error = machine.last_error();
    REQUIRE(error);
    CHECK(error->failure == SequenceFailure::MasterInactive);
    CHECK(bus.requests().size() == 1);  // the slave count, refused: nothing more was tried
    {
        std::lock_guard lock(done_mutex);
        REQUIRE(done);
        CHECK(done->reached == MasterState::Init);
        REQUIRE(done->error);
        CHECK(done->error->failure == SequenceFailure::MasterInactive);
    }
    for (const auto& report : events.pop_all(std::chrono::milliseconds(0))) {
        CHECK(report.event.kind != master::events::kTransitionFailed);
    }
}

TEST_CASE("Requesting the current state sends nothing", "[sequencer][sm]") {
    ScriptedBus bus([](const bus::DatagramRequest& r) { return reply(r.data, 0); });
    VirtualClock clock;
    sequencer::MasterStateMachine machine(cherry(), bus, {}, nullptr, clock);
    machine.request(MasterState::Init);
    REQUIRE(machine.wait_idle(std::chrono::seconds(10)));
    CHECK(machine.current() == MasterState::Init);
    CHECK_FALSE(machine.last_error());
    CHECK(bus.requests().empty());
}

}  // namespace
}  // namespace ecpair::test
