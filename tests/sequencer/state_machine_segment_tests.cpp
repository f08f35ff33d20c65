// MasterStateMachine over the simulated segment with real ENI files:
// INIT -> PREOP -> SAFEOP -> OP and back to INIT, the DC start time, the
// made-up commands of Advantech's dialect, a bus mismatch that keeps the
// master in INIT, an absent Hot-Connect group, a slave in ERROR, and an
// INACTIVE master.
//
// Tests tagged [coe-server] run the ENIs' CoE InitCmds too: they need the
// simulated slaves' CoE server (sim/esc).

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>

#include "ecpair/common/bytes.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sim/eoe_server.hpp"
#include "ecpair/wire/eoe.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "fakes.hpp"
#include "segment_fixture.hpp"

namespace ecpair::test {
namespace {

using sequencer::MasterState;
using sequencer::MasterStateMachine;
using sequencer::SequenceFailure;

std::uint8_t al_state(SimulatedBus& sim, std::size_t position) {
    return static_cast<std::uint8_t>(sim.segment.slave(position).al_status() & 0x0F);
}

bool all_in(SimulatedBus& sim, eni::SlaveState state) {
    for (std::size_t p = 1; p <= sim.segment.slave_count(); ++p) {
        if (al_state(sim, p) != static_cast<std::uint8_t>(state)) return false;
    }
    return true;
}

void up_and_down(const std::shared_ptr<const eni::EniConfig>& eni) {
    SimulatedBus sim(*eni);
    VirtualClock clock;
    FakeCyclicMaster cyclic;
    master::EventQueue events;
    MasterStateMachine machine(eni, sim.bus, cyclic.hooks(), &events, clock);

    const auto up = run_to(machine, MasterState::Op);
    INFO(eni->source_path << ": " << (up ? up->message : std::string("reached OP")));
    REQUIRE_FALSE(up);
    CHECK(machine.current() == MasterState::Op);
    CHECK(all_in(sim, eni::SlaveState::Op));
    for (std::size_t p = 1; p <= sim.segment.slave_count(); ++p) {
        CHECK(sim.segment.slave(p).station_address() == eni->slaves[p - 1].info.phys_addr);
    }
    CHECK(cyclic.applied() ==
          std::vector<eni::SlaveState>{eni::SlaveState::Preop, eni::SlaveState::Safeop, eni::SlaveState::Op});

    const auto down = run_to(machine, MasterState::Init);
    INFO((down ? down->message : std::string("reached INIT")));
    REQUIRE_FALSE(down);
    CHECK(machine.current() == MasterState::Init);
    CHECK(all_in(sim, eni::SlaveState::Init));
    CHECK(cyclic.applied().back() == eni::SlaveState::Init);

    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    CHECK(std::any_of(seen.begin(), seen.end(), [](const master::EventReport& r) {
        return r.event.kind == master::events::kBusScanStatus && r.event.c == 1;
    }));
    CHECK(std::none_of(seen.begin(), seen.end(),
                       [](const master::EventReport& r) { return r.event.kind == master::events::kTransitionFailed; }));
}

TEST_CASE("INIT -> OP -> INIT with real ENIs whose CoE InitCmds are removed", "[sequencer][sm][segment]") {
    const auto name = GENERATE(as<std::string>{}, "twincat_cherryecat_cia402_1slave.xml",
                               "ecengineer_rocos_elmo_3slaves_bcr.xml", "twincat_kpierczy_5slaves.xml");
    up_and_down(without_coe_init_cmds(load_eni_copy(name)));
}

TEST_CASE("INIT -> OP -> INIT with the made-up InitCmds of an Advantech ENI", "[sequencer][sm][segment]") {
    up_and_down(load_eni_copy("advantech_io_ring_4slaves.xml"));
}

TEST_CASE("INIT -> OP -> INIT with real ENIs including their CoE InitCmds", "[sequencer][sm][segment][coe-server]") {
    const auto name = GENERATE(as<std::string>{}, "twincat_cherryecat_cia402_1slave.xml",
                               "ecengineer_rocos_elmo_3slaves_bcr.xml", "advantech_amax4270_1slave.xml");
    up_and_down(load_eni_copy(name));
}

// Issue 27: EoE InitCmds run, not skipped: Elmo's EAS writes the set-IP data
// without the EoE header (PS), EC-Engineer with it (IP), and the SoE drive
// of soe_eoe_drive_2slaves has SoE InitCmds too.
TEST_CASE("INIT -> OP -> INIT with EoE and SoE InitCmds, the slaves hold the IP parameters the ENI sets",
          "[sequencer][sm][segment][coe-server][eoe]") {
    const auto [name, slave, ip] = GENERATE(table<std::string, std::size_t, std::string>(
        {{"elmo_eas_rocos_1slave.xml", 1, "192.168.1.4"},
         {"ecengineer_murrelektronik_encrypted_2slaves.xml", 2, "192.168.0.102"},
         {"eni_extra/soe_eoe_drive_2slaves.xml", 2, "10.0.0.2"}}));
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy(name);
    SimulatedBus sim(*eni);
    VirtualClock clock;
    FakeCyclicMaster cyclic;
    MasterStateMachine machine(eni, sim.bus, cyclic.hooks(), nullptr, clock);
    const auto up = run_to(machine, MasterState::Op);
    INFO(name << ": " << (up ? up->message : std::string("reached OP")));
    REQUIRE_FALSE(up);
    const auto* eoe = sim.segment.slave(slave).eoe_server();
    REQUIRE(eoe != nullptr);
    REQUIRE(eoe->ip_parameters().ip);
    CHECK(wire::ipv4_text(*eoe->ip_parameters().ip) == ip);
    REQUIRE_FALSE(run_to(machine, MasterState::Init));
}

// Issue 11, findings 1 and 2, and a tree (item 3): synthetic ENIs of the
// shapes real configurators export (tests/data/eni_extra).
TEST_CASE("INIT -> OP -> INIT with what real configurators export for real slaves", "[sequencer][sm][segment][fidelity]") {
    // twincat_mailbox_irq: mailbox SMs written with 0x36/0x32 (ECAT event bit);
    // digital_io_device_emulation: an EL2008 whose output SM is set only in SAFEOP -> OP;
    // tree_ek1122: an EK1122 junction with branches on ports D, B and C.
    const auto name = GENERATE(as<std::string>{}, "eni_extra/twincat_mailbox_irq_2slaves.xml",
                               "eni_extra/digital_io_device_emulation_3slaves.xml", "eni_extra/tree_ek1122_7slaves.xml");
    up_and_down(load_eni_copy(name));
}

TEST_CASE("The EL2008 is in SAFEOP with its output SM disabled and in OP with it enabled", "[sequencer][sm][segment][fidelity]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/digital_io_device_emulation_3slaves.xml");
    SimulatedBus sim(*eni);
    VirtualClock clock;
    MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock);
    const auto sm0_enabled = [&] { return (sim.segment.slave(2).read_memory(0x0806, 1).at(0) & 0x01) != 0; };
    auto error = run_to(machine, MasterState::Safeop);
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    CHECK(al_state(sim, 2) == 4);
    CHECK_FALSE(sm0_enabled());
    error = run_to(machine, MasterState::Op);
    REQUIRE_FALSE(error);
    CHECK(al_state(sim, 2) == 8);
    CHECK(sm0_enabled());
    error = run_to(machine, MasterState::Safeop);
    REQUIRE_FALSE(error);
    CHECK(al_state(sim, 2) == 4);
    CHECK_FALSE(sm0_enabled());
    // Both terminals run in device emulation (the coupler, without process data, needs no checks either);
    // nothing refused a request.
    for (std::size_t p = 2; p <= 3; ++p) CHECK((sim.segment.slave(p).read_memory(0x0141, 1).at(0) & 0x01) == 0x01);
    for (std::size_t p = 1; p <= 3; ++p) CHECK(sim.segment.slave(p).al_status_code() == 0);
}

TEST_CASE("The DC start time written during PS is in the future of the reference clock, on a cycle boundary",
          "[sequencer][sm][segment][dc]") {
    const std::shared_ptr<const eni::EniConfig> eni =
        without_coe_init_cmds(load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml"));
    SimulatedBus sim(*eni);
    VirtualClock clock;
    MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock);
    const auto error = run_to(machine, MasterState::Safeop);
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    for (std::size_t p = 1; p <= 3; ++p) {
        const auto start = load_le<std::uint64_t>(sim.segment.slave(p).read_memory(wire::reg::kDcStartTime, 8), 0);
        CHECK(start != 0);
        CHECK(start % 1'000'000 == 0);  // CycleTime0 1 ms, ShiftTime 0
    }
}

TEST_CASE("A bus mismatch keeps the master in INIT and says why", "[sequencer][sm][segment]") {
    const std::shared_ptr<const eni::EniConfig> eni =
        without_coe_init_cmds(load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml"));
    auto wiring = std::make_shared<eni::EniConfig>(*eni);
    wiring->slaves.pop_back();
    SimulatedBus sim(*wiring);
    VirtualClock clock;
    master::EventQueue events;
    MasterStateMachine machine(eni, sim.bus, {}, &events, clock);

    const auto error = run_to(machine, MasterState::Op);
    REQUIRE(error);
    CHECK(error->failure == SequenceFailure::BusMismatch);
    CHECK(error->slave_index == std::size_t{2});
    CHECK_THAT(error->message, Catch::StartsWith("bus mismatch: position 2 (after station 1002 port B): configured"));
    CHECK(machine.current() == MasterState::Init);
    CHECK(all_in(sim, eni::SlaveState::Init));

    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    const auto has = [&seen](master::EventKind kind, std::uint32_t a, std::uint32_t b) {
        return std::any_of(seen.begin(), seen.end(),
                           [&](const master::EventReport& r) {
                               return r.event.kind == kind && r.event.a == a && r.event.b == b;
                           });
    };
    CHECK(has(master::events::kBusScanStatus, 2, 3));
    CHECK(has(master::events::kBusMismatch, 2, static_cast<std::uint32_t>(bus::SlaveMatch::Missing)));
    CHECK(has(master::events::kSlavePresence, 2, 0));
    CHECK(has(master::events::kSlavePresence, 0, 1));
}

TEST_CASE("An absent Hot-Connect group is skipped and the slaves behind it reach OP", "[sequencer][sm][segment]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/hotconnect_groups_4slaves.xml");
    auto wiring = std::make_shared<eni::EniConfig>(*eni);
    wiring->slaves.erase(wiring->slaves.begin() + 1, wiring->slaves.begin() + 3);
    SimulatedBus sim(*wiring);
    VirtualClock clock;
    MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock);
    const auto error = run_to(machine, MasterState::Op);
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    CHECK(machine.presence() == std::vector<bool>{true, false, false, true});
    CHECK(all_in(sim, eni::SlaveState::Op));
    CHECK(sim.segment.slave(2).station_address() == 1004);  // the tool changer, now at position 1
}

TEST_CASE("ETG.1020: a slave refusing SAFEOP with 0x0061 is taken through INIT and reaches OP",
          "[sequencer][sm][segment][hotconnect]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/hotconnect_groups_4slaves.xml");
    SimulatedBus sim(*eni);
    // The gripper drive's SII alias is 7 (its identification); a rotary switch set to 7 races it.
    REQUIRE(sim.segment.set_legacy_id_selector(2, 7));
    REQUIRE(sim.segment.power_off(2));
    REQUIRE(sim.segment.power_on(2));
    VirtualClock clock;
    master::EventQueue events;
    MasterStateMachine machine(eni, sim.bus, {}, &events, clock);
    const auto error = run_to(machine, MasterState::Op);
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    CHECK(all_in(sim, eni::SlaveState::Op));
    CHECK(sim.segment.slave(2).station_alias() == 7);
    const auto all = events.pop_all(std::chrono::milliseconds(0));
    const bool updated = std::any_of(all.begin(), all.end(), [](const master::EventReport& r) {
        return r.event.kind == master::events::kSlaveIdentificationUpdated && r.event.a == 1 && r.event.b == 7;
    });
    CHECK(updated);
}

TEST_CASE("ETG.1020: a slave whose new alias is not the ENI's is refused with both values named",
          "[sequencer][sm][segment][hotconnect]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/hotconnect_groups_4slaves.xml");
    SimulatedBus sim(*eni);
    REQUIRE(sim.segment.set_legacy_id_selector(2, 9));
    REQUIRE(sim.segment.power_off(2));
    REQUIRE(sim.segment.power_on(2));
    VirtualClock clock;
    MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock);
    const auto error = run_to(machine, MasterState::Op);
    // The startup scan already sees alias 9 where 7 belongs: the gripper group is refused,
    // the rest of the bus goes to OP.
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    CHECK(machine.presence() == std::vector<bool>{true, false, false, true});
    CHECK(al_state(sim, 1) == static_cast<std::uint8_t>(eni::SlaveState::Op));
    CHECK(al_state(sim, 4) == static_cast<std::uint8_t>(eni::SlaveState::Op));
}

TEST_CASE("A slave in ERROR is acknowledged before its commands run", "[sequencer][sm][segment]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("advantech_io_ring_4slaves.xml");
    SimulatedBus sim(*eni);
    // An INIT -> OP request is refused by the slave: ERROR with code 0x0011.
    bus::DatagramRequest wrong;
    wrong.command = wire::Command::Apwr;
    wrong.address = wire::DatagramHeader::physical(0, wire::reg::kAlControl);
    wrong.data = {0x08, 0x00};
    REQUIRE(sim.bus.exchange(wrong));
    REQUIRE((sim.segment.slave(1).al_status() & 0x10) != 0);

    VirtualClock clock;
    master::EventQueue events;
    MasterStateMachine machine(eni, sim.bus, {}, &events, clock);
    const auto error = run_to(machine, MasterState::Preop);
    INFO((error ? error->message : std::string()));
    REQUIRE_FALSE(error);
    CHECK(al_state(sim, 1) == 2);
    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    CHECK(std::any_of(seen.begin(), seen.end(), [](const master::EventReport& r) {
        return r.event.kind == master::events::kSlaveStateError && r.event.a == 0 && (r.event.b & 0x10) != 0 &&
               r.event.c == 0x0011;
    }));
}

TEST_CASE("A failing InitCmd stops the sequence with the slave, line and AL status", "[sequencer][sm][segment]") {
    auto eni = without_coe_init_cmds(load_eni_copy("twincat_cherryecat_cia402_1slave.xml"));
    // Make the PS "set sm 2 (outputs)" write a config the slave refuses for SAFEOP: a disabled outputs SM.
    for (auto& cmd : eni->slaves[0].init_cmds) {
        if (cmd.transitions.contains(eni::Transition::PS) && cmd.ado == wire::reg::kSmBase + 2 * wire::reg::kSmSize) {
            cmd.data[6] = 0x00;
        }
    }
    const std::shared_ptr<const eni::EniConfig> config = eni;
    SimulatedBus sim(*config);
    VirtualClock clock;
    master::EventQueue events;
    MasterStateMachine machine(config, sim.bus, {}, &events, clock);
    const auto error = run_to(machine, MasterState::Op);
    REQUIRE(error);
    INFO(error->message);
    CHECK(error->failure == SequenceFailure::InitCmd);
    CHECK(error->from == MasterState::Preop);
    CHECK(error->to == MasterState::Safeop);
    CHECK(error->slave_index == std::size_t{0});
    CHECK_THAT(error->message, Catch::StartsWith("transition PS: slave '") && Catch::Contains("ENI line") &&
                                   Catch::Contains("AL status PREOP+ERR, code 0x"));
    CHECK(machine.current() == MasterState::Preop);
    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    CHECK(std::any_of(seen.begin(), seen.end(), [](const master::EventReport& r) {
        return r.event.kind == master::events::kTransitionFailed && r.event.a == 2 && r.event.b == 4 && r.event.c == 0;
    }));
}

TEST_CASE("A master that becomes INACTIVE mid-way stops quietly", "[sequencer][sm][segment]") {
    const std::shared_ptr<const eni::EniConfig> eni =
        without_coe_init_cmds(load_eni_copy("twincat_cherryecat_cia402_1slave.xml"));
    SimulatedBus sim(*eni);
    VirtualClock clock;
    FakeCyclicMaster cyclic;
    auto hooks = cyclic.hooks();
    auto apply = hooks.request_cyclic_state;
    hooks.request_cyclic_state = [apply, &sim](eni::SlaveState s) {
        apply(s);
        if (s == eni::SlaveState::Preop) sim.bus.refuse(bus::BusErrc::MasterRedStateInactive);
    };
    master::EventQueue events;
    MasterStateMachine machine(eni, sim.bus, hooks, &events, clock);
    const auto error = run_to(machine, MasterState::Op);
    REQUIRE(error);
    CHECK(error->failure == SequenceFailure::MasterInactive);
    CHECK(machine.current() == MasterState::Preop);
    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    CHECK(std::none_of(seen.begin(), seen.end(),
                       [](const master::EventReport& r) { return r.event.kind == master::events::kTransitionFailed; }));
}

// A PS that failed at its second slave leaves the first in SAFEOP, where its
// PS CoE InitCmds (the PDO assignment) are refused. Run again as it was, the
// transition would fail at that first slave every time; it takes the slave
// back to PREOP first.
TEST_CASE("A PREOP -> SAFEOP that stopped halfway runs again from PREOP: slaves already in SAFEOP go back first",
          "[sequencer][sm][segment][coe-server]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml");
    REQUIRE(eni->slaves.size() == 3);
    SimulatedBus sim(*eni);
    const std::uint16_t second = eni->slaves[1].info.phys_addr;
    std::atomic<bool> lose_safeop_request{true};
    ScriptedBus bus([&](const bus::DatagramRequest& r) {
        const bool safeop_request = r.command == wire::Command::Fpwr && adp_of(r) == second &&
                                    ado_of(r) == wire::reg::kAlControl && !r.data.empty() && (r.data[0] & 0x0F) == 0x04;
        if (lose_safeop_request && safeop_request) return bus_error(bus::BusErrc::Timeout);
        return sim.bus.exchange(r);
    });
    VirtualClock clock;
    FakeCyclicMaster cyclic;
    master::EventQueue events;
    MasterStateMachine machine(eni, bus, cyclic.hooks(), &events, clock);

    const auto first = run_to(machine, MasterState::Op);
    REQUIRE(first);
    INFO(first->message);
    REQUIRE(first->from == MasterState::Preop);
    REQUIRE(first->slave_index == std::size_t{1});
    REQUIRE(machine.current() == MasterState::Preop);
    REQUIRE(al_state(sim, 1) == 4);  // the first slave made it to SAFEOP

    lose_safeop_request = false;
    const auto again = run_to(machine, MasterState::Op);
    INFO((again ? again->message : std::string("reached OP")));
    CHECK_FALSE(again);
    CHECK(machine.current() == MasterState::Op);
    CHECK(all_in(sim, eni::SlaveState::Op));
}

}  // namespace
}  // namespace ecpair::test
