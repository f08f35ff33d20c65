// The transition function and the order of a transition's commands, on
// real ENI files: CoE InitCmds before the AL control write (after it for
// IP), master commands around the slaves, absent slaves left out, and the
// made-up commands for an ENI without ESC InitCmds.

#include <catch2/catch.hpp>

#include <algorithm>
#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/sequencer/transition_plan.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::test {
namespace {

using eni::Transition;
using sequencer::MasterState;

std::shared_ptr<const eni::EniConfig> load(const std::string& name) {
    auto loaded = eni::load_eni_file(fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, name));
    REQUIRE(loaded);
    return *loaded;
}

const eni::EcatCmd* ecat(const sequencer::SlaveStep& step) { return std::get_if<eni::EcatCmd>(&step); }

// Index of the first step that is a CoE InitCmd / the AL control write requesting `state`.
std::ptrdiff_t first_coe(const sequencer::SlavePlan& plan) {
    const auto it = std::find_if(plan.steps.begin(), plan.steps.end(),
                                 [](const sequencer::SlaveStep& s) { return std::holds_alternative<eni::CoeInitCmd>(s); });
    return it - plan.steps.begin();
}
std::ptrdiff_t state_request(const sequencer::SlavePlan& plan, eni::SlaveState state) {
    const auto it = std::find_if(plan.steps.begin(), plan.steps.end(), [state](const sequencer::SlaveStep& s) {
        const auto* cmd = ecat(s);
        return cmd && sequencer::requested_al_state(*cmd) == static_cast<std::uint8_t>(state);
    });
    return it - plan.steps.begin();
}

TEST_CASE("The transition function goes up one state at a time and down as the ENI allows", "[sequencer][plan]") {
    const auto twincat = load("twincat_cherryecat_cia402_1slave.xml");  // has OI, SI, PI, OS, SP, OP commands
    CHECK(sequencer::next_transition(MasterState::Init, MasterState::Op, *twincat) == Transition::IP);
    CHECK(sequencer::next_transition(MasterState::Preop, MasterState::Op, *twincat) == Transition::PS);
    CHECK(sequencer::next_transition(MasterState::Safeop, MasterState::Op, *twincat) == Transition::SO);
    CHECK_FALSE(sequencer::next_transition(MasterState::Op, MasterState::Op, *twincat));
    CHECK(sequencer::next_transition(MasterState::Op, MasterState::Init, *twincat) == Transition::OI);
    CHECK(sequencer::next_transition(MasterState::Op, MasterState::Preop, *twincat) == Transition::OP);
    CHECK(sequencer::next_transition(MasterState::Safeop, MasterState::Init, *twincat) == Transition::SI);

    SECTION("without commands for the direct way down: one state at a time") {
        auto copy = std::make_shared<eni::EniConfig>(*twincat);
        for (auto& cmd : copy->slaves[0].init_cmds) {
            auto kept = eni::TransitionSet{};
            for (auto t : {Transition::IP, Transition::PS, Transition::SO, Transition::OS, Transition::SP, Transition::PI}) {
                if (cmd.transitions.contains(t)) kept.add(t);
            }
            cmd.transitions = kept;
        }
        CHECK(sequencer::next_transition(MasterState::Op, MasterState::Init, *copy) == Transition::OS);
        CHECK(sequencer::next_transition(MasterState::Safeop, MasterState::Init, *copy) == Transition::SP);
        CHECK(sequencer::next_transition(MasterState::Preop, MasterState::Init, *copy) == Transition::PI);
    }
    SECTION("no ESC InitCmds at all (made up): straight down") {
        const auto advantech = load("advantech_io_ring_4slaves.xml");
        CHECK(sequencer::next_transition(MasterState::Op, MasterState::Init, *advantech) == Transition::OI);
    }
}

TEST_CASE("PS: ESC commands, then CoE commands, then the AL control write and its check", "[sequencer][plan]") {
    const auto twincat = load("twincat_cherryecat_cia402_1slave.xml");
    const auto plan = sequencer::plan_transition(*twincat, Transition::PS, {true});
    REQUIRE(plan.slaves.size() == 1);
    const auto& steps = plan.slaves[0];
    const auto coe = first_coe(steps);
    const auto safeop = state_request(steps, eni::SlaveState::Safeop);
    REQUIRE(coe < static_cast<std::ptrdiff_t>(steps.steps.size()));
    REQUIRE(safeop < static_cast<std::ptrdiff_t>(steps.steps.size()));
    CHECK(coe > 0);                // SM and FMMU writes come first
    CHECK(safeop == coe + 2);      // the two PS CoE commands (PDO assignment) right before SAFEOP is requested
    const auto* check = ecat(steps.steps.back());
    REQUIRE(check);
    CHECK(check->ado == wire::reg::kAlStatus);
    CHECK(check->validate);
}

TEST_CASE("IP: CoE commands run last, when the mailbox works", "[sequencer][plan]") {
    auto copy = std::make_shared<eni::EniConfig>(*load("twincat_cherryecat_cia402_1slave.xml"));
    eni::CoeInitCmd cmd;
    cmd.transitions.add(Transition::IP);
    cmd.index = 0x8000;
    copy->slaves[0].mailbox->coe_init_cmds.push_back(cmd);
    const auto plan = sequencer::plan_transition(*copy, Transition::IP, {true});
    const auto& steps = plan.slaves[0].steps;
    CHECK(std::holds_alternative<eni::CoeInitCmd>(steps.back()));
    CHECK(first_coe(plan.slaves[0]) == static_cast<std::ptrdiff_t>(steps.size()) - 1);
    CHECK(state_request(plan.slaves[0], eni::SlaveState::Preop) < first_coe(plan.slaves[0]));
    // The master's IP commands are all BeforeSlave in this file.
    CHECK_FALSE(plan.master_before.empty());
    CHECK(plan.master_after.empty());
}

TEST_CASE("Absent slaves have no part in a transition", "[sequencer][plan]") {
    const auto elmo = load("ecengineer_rocos_elmo_3slaves_bcr.xml");
    const auto plan = sequencer::plan_transition(*elmo, Transition::IP, {true, false, true});
    REQUIRE(plan.slaves.size() == 2);
    CHECK(plan.slaves[0].slave_index == 0);
    CHECK(plan.slaves[1].slave_index == 2);
    CHECK_FALSE(plan.slaves[0].synthesized);
}

TEST_CASE("An ENI without ESC InitCmds gets made-up ones", "[sequencer][plan]") {
    const auto advantech = load("advantech_io_ring_4slaves.xml");
    const auto ip = sequencer::plan_transition(*advantech, Transition::IP, {true, true, true, true});
    REQUIRE(ip.slaves.size() == 4);
    const auto& coupler = ip.slaves[0];
    CHECK(coupler.synthesized);
    const auto& info = advantech->slaves[0].info;

    std::vector<const eni::EcatCmd*> cmds;
    for (const auto& s : coupler.steps) cmds.push_back(ecat(s));
    REQUIRE(std::all_of(cmds.begin(), cmds.end(), [](const eni::EcatCmd* c) { return c != nullptr; }));
    // INIT with acknowledge by position, its check, the station address by position.
    CHECK(cmds[0]->command == wire::Command::Apwr);
    CHECK(cmds[0]->adp == 0);
    CHECK(cmds[0]->data == std::vector<std::uint8_t>{0x11, 0x00});
    CHECK(cmds[1]->validate);
    CHECK(cmds[2]->ado == wire::reg::kStationAddress);
    CHECK(load_le<std::uint16_t>(cmds[2]->data, 0) == info.phys_addr);
    // The second slave (positive AutoIncAddr 1 in this file) is addressed at position 1 = ADP 0xFFFF,
    // and has no mailbox, so no SM0/SM1 writes.
    const auto& second = ip.slaves[1].steps;
    CHECK(ecat(second.front())->adp == 0xFFFF);
    CHECK(std::none_of(second.begin(), second.end(), [](const sequencer::SlaveStep& s) {
        return ecat(s)->ado == wire::reg::kSmBase;
    }));
    // SM0/SM1 from the ENI's Sm0/Sm1 (MBoxOut/MBoxIn), by station address.
    const auto sm0 = std::find_if(cmds.begin(), cmds.end(), [](const eni::EcatCmd* c) {
        return c->ado == wire::reg::kSmBase && c->data.size() == wire::SyncManagerConfig::kSize;
    });
    REQUIRE(sm0 != cmds.end());
    CHECK((*sm0)->command == wire::Command::Fpwr);
    CHECK((*sm0)->adp == info.phys_addr);
    const auto config = wire::SyncManagerConfig::decode((*sm0)->data);
    CHECK(config.physical_start == 4096);
    CHECK(config.length == 128);
    CHECK(config.control == 38);
    CHECK(config.enabled());
    // Then PREOP is requested and checked.
    CHECK(sequencer::requested_al_state(*cmds[cmds.size() - 2]) == std::uint8_t{2});
    CHECK(cmds.back()->validate);

    const auto ps = sequencer::plan_transition(*advantech, Transition::PS, {true, true, true, true});
    const auto& ps_steps = ps.slaves[0].steps;
    const auto sm3 = std::find_if(ps_steps.begin(), ps_steps.end(), [](const sequencer::SlaveStep& s) {
        return ecat(s) && ecat(s)->ado == wire::reg::kSmBase + 3 * wire::reg::kSmSize;
    });
    REQUIRE(sm3 != ps_steps.end());
    const auto inputs = wire::SyncManagerConfig::decode(ecat(*sm3)->data);
    CHECK(inputs.physical_start == 5120);
    CHECK(inputs.length == 24);
    CHECK(inputs.enabled());
    CHECK(sequencer::requested_al_state(*ecat(ps_steps[ps_steps.size() - 2])) == std::uint8_t{4});
}

}  // namespace
}  // namespace ecpair::test
