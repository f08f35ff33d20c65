#pragma once
// Brings the slaves of Hot-Connect groups that just appeared to a state
// while the rest of the bus stays where it is (hot-connect.md §3): for each
// transition on the way (IP, PS, SO) the ENI's commands of those slaves
// only, in the order of transition_plan.hpp (ESC InitCmds, mailbox InitCmds),
// addressed where the slaves are now (their auto-increment addresses moved
// by their position shift). The master's own InitCmds of a transition are
// broadcasts meant for a bus starting up: a write (BWR: clearing FMMUs,
// SyncManagers...) is sent to each new slave instead (APWR, expecting 1); a
// read (BRD) is left out.
//
// Where the slaves start from: reset_first (automatic and manual-PREOP
// modes) takes them through INIT whatever they were in; otherwise (manual,
// no reset) each group goes on from the state its slaves are in, unless a
// slave lacks its station address. A slave refusing SAFEOP with 0x0061
// (ETG.1020) goes through INIT and again (identification_update.hpp). A
// slave identified by an input word is checked in SAFEOP, where its inputs
// first run: a wrong value stops the bring-up there.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/event.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/sequencer/mailbox_init_cmd_runner.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sequencer/transition_plan.hpp"

namespace ecpair::hotconnect {

struct BringUpRequest {
    std::vector<std::size_t> slaves;             // ENI indices, ring order
    std::vector<std::uint16_t> position_shift;   // per ENI slave: configured minus found position
    std::vector<bool> present;                   // per ENI slave, for the DC reference clock
    sequencer::MasterState target = sequencer::MasterState::Op;
    bool reset_first = true;
};

struct BringUpFailure {
    std::size_t slave = 0;  // ENI index
    std::string message;
    std::optional<std::uint16_t> al_status_code;
};

struct BringUpResult {
    sequencer::MasterState reached = sequencer::MasterState::Init;
    std::optional<BringUpFailure> failure;
};

class GroupBringUp {
public:
    // `raise` reports an event (the caller stamps the cycle).
    GroupBringUp(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, sequencer::Clock& clock,
                 std::function<void(master::EventKind, std::uint32_t, std::uint32_t)> raise);
    ~GroupBringUp();

    // `reached_safeop` is called once the slaves are in SAFEOP (their process
    // data runs from then on), before SAFEOP -> OP.
    BringUpResult run(const BringUpRequest& request, const std::function<void()>& reached_safeop,
                      std::stop_token stop);

private:
    std::optional<BringUpFailure> run_transition(const BringUpRequest& request, eni::Transition t, std::stop_token stop);
    std::optional<BringUpFailure> run_slave(const BringUpRequest& request, const sequencer::SlavePlan& plan,
                                            eni::Transition t, std::stop_token stop, bool may_recover);
    std::optional<BringUpFailure> recover(const BringUpRequest& request, const sequencer::SlavePlan& plan,
                                          eni::Transition t, std::stop_token stop);
    std::optional<sequencer::MasterState> common_state(const BringUpRequest& request);
    // Slaves identified by an input word show the ENI's value in SAFEOP (else a failure).
    std::optional<BringUpFailure> check_input_words(const BringUpRequest& request);
    sequencer::CommandContext context_for(const BringUpRequest& request, std::size_t slave) const;

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    sequencer::Clock& clock_;
    std::function<void(master::EventKind, std::uint32_t, std::uint32_t)> raise_;
    sequencer::InitCmdRunner init_cmds_;
    sequencer::SlaveMailboxes mailboxes_;
    sequencer::MailboxInitCmdRunner mailbox_init_cmds_;
};

}  // namespace ecpair::hotconnect
