#pragma once
// The master's EtherCAT state machine: brings the slaves from INIT through
// PREOP and SAFEOP to OP and back, as the ENI prescribes, on a worker
// thread of its own. request() only records the target; the worker runs
// the transitions (next_transition) one after the other, re-reading the
// target after each, so a new request redirects a running sequence at the
// next state boundary.
//
// Each transition (transition_plan.hpp for the order of commands):
//   - before IP, the startup scan: a mismatch of a mandatory slave stops the
//     master in INIT (events BusScanStatus, BusMismatch, SlavePresence);
//   - every present slave is first checked for an error flag in AL status;
//     one in ERROR is reported (SlaveStateError) and acknowledged (AL control
//     with bit 4) before its commands run, so a retry starts clean;
//   - the commands run through InitCmdRunner / MailboxInitCmdRunner (CoE,
//     SoE, EoE), the latter over the slaves' shared mailboxes;
//   - the cyclic master is told the new state (hooks) and the worker waits
//     until it applies: after the slaves going up, before them going down
//     (so the cyclic frames never expect more than the slaves do).
// A failure stops the sequence where it is (TransitionFailed, last_error()).
// When the bus says the master is INACTIVE or the request was cancelled, the
// sequence stops quietly and last_error() says so. Every transition and its
// duration is logged.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/sequencer/mailbox_init_cmd_runner.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sequencer/startup_scan.hpp"
#include "ecpair/sequencer/transition_plan.hpp"

namespace ecpair::sequencer {

enum class SequenceFailure : std::uint8_t {
    BusMismatch,            // the startup scan found the bus different from the ENI
    ScanFailed,             // the startup scan itself could not run
    InitCmd,                // an ESC or master InitCmd failed
    MailboxInitCmd,         // a CoE, SoE or EoE InitCmd failed
    CyclicStateNotApplied,  // the cyclic master did not take the new state in time
    MasterInactive,         // the bus refused: the master is INACTIVE
    Cancelled,              // the bus cancelled the request (master shutting down or changing role)
    Stopped,                // the state machine is being destroyed
};

std::string_view to_string(SequenceFailure failure);

struct SequenceError {
    SequenceFailure failure = SequenceFailure::InitCmd;
    MasterState from = MasterState::Init;  // the transition that failed
    MasterState to = MasterState::Init;
    std::optional<std::size_t> slave_index;  // the slave it failed at (EniConfig::slaves), if any
    std::string message;
};

struct SequenceResult {
    MasterState target = MasterState::Init;
    MasterState reached = MasterState::Init;
    std::optional<SequenceError> error;
};

struct StateMachineHooks {
    // Tell the cyclic master which state's cyclic commands to send (Master::request_state).
    std::function<void(eni::SlaveState)> request_cyclic_state;
    // The state the cyclic master applies now (Master::state).
    std::function<eni::SlaveState()> cyclic_state;
    // Called on the worker thread when a sequence ends (reached, failed or stopped).
    std::function<void(const SequenceResult&)> on_done;
    // Called on the worker thread when it starts a sequence (before any transition).
    std::function<void()> on_start;
    // Called on the worker thread after each startup scan, before anything is
    // sent to the slaves (Hot-Connect corrects the expected WKCs from it).
    std::function<void(const ScanOutcome&)> on_scan;
};

struct StateMachineOptions {
    std::chrono::milliseconds cyclic_state_timeout{1000};
    InitCmdOptions init_cmds;
    // The slaves' mailboxes, shared with the mailbox service (null: the state
    // machine keeps its own). Must outlive the state machine.
    SlaveMailboxes* mailboxes = nullptr;
};

class MasterStateMachine {
public:
    MasterStateMachine(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, StateMachineHooks hooks,
                       master::EventQueue* events = nullptr, Clock& clock = steady_clock(),
                       StateMachineOptions options = {});
    ~MasterStateMachine();
    MasterStateMachine(const MasterStateMachine&) = delete;
    MasterStateMachine& operator=(const MasterStateMachine&) = delete;

    // Non-blocking: records the target; the worker gets there (or fails).
    void request(MasterState target);
    // Takes `state` as reached without running any transition: a hot-standby
    // takeover, where the partner already brought the slaves there. Meant for
    // an idle machine (an INACTIVE master's sequences stop at once).
    void adopt(MasterState state);
    // After a takeover: the mailbox counters the previous ACTIVE used last,
    // per slave in ENI order (0: none seen); each slave's next mailbox message
    // continues after it (SlaveMailboxes::continue_after).
    void continue_mailbox_counters(const std::vector<std::uint8_t>& last_counters);

    MasterState target() const;
    MasterState current() const;
    bool busy() const;
    std::optional<SequenceError> last_error() const;
    // Per EniConfig::slaves entry, from the last startup scan (all true before
    // the first) or from Hot-Connect since.
    std::vector<bool> presence() const;
    std::vector<std::uint16_t> position_shift() const;
    // Hot-Connect changed which slaves are on the bus and where: the next
    // transitions take those (the next startup scan decides anew).
    void update_presence(std::vector<bool> present, std::vector<std::uint16_t> position_shift);
    // Waits until no sequence runs (its on_done included) or `timeout` passes; true when idle.
    bool wait_idle(std::chrono::milliseconds timeout) const;

private:
    void worker(std::stop_token stop);
    std::optional<SequenceError> run_transition(eni::Transition t, std::stop_token stop);
    std::optional<SequenceError> startup_scan(std::stop_token stop);
    // An upward transition starts with every slave at its source state (state_rollback.hpp).
    std::optional<SequenceError> take_back_slaves_ahead_of(MasterState state, const TransitionPlan& plan,
                                                           eni::Transition t, std::stop_token stop);
    std::optional<SequenceError> run_slave(const SlavePlan& plan, eni::Transition t, std::stop_token stop,
                                           bool may_recover = true);
    std::optional<SequenceError> recover_identification_update(const SlavePlan& plan, eni::Transition t,
                                                               std::stop_token stop);
    std::optional<SequenceError> apply_cyclic_state(MasterState state, eni::Transition t, std::stop_token stop);
    void acknowledge_error(std::size_t slave_index, eni::Transition t);
    CommandContext context_for(std::size_t slave_index) const;
    SequenceError from_init_cmd(const InitCmdError& error, eni::Transition t) const;
    void raise(master::EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0);
    void finish(MasterState target, std::optional<SequenceError> error);

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    StateMachineHooks hooks_;
    master::EventQueue* events_;
    Clock& clock_;
    StateMachineOptions options_;
    InitCmdRunner init_cmds_;
    std::unique_ptr<SlaveMailboxes> own_mailboxes_;  // when none are given
    SlaveMailboxes& mailboxes_;
    MailboxInitCmdRunner mailbox_init_cmds_;

    // Worker-thread state (position_shift_ also written by update_presence, under the mutex).
    std::vector<std::uint16_t> position_shift_;

    mutable std::mutex mutex_;
    mutable std::condition_variable_any changed_;
    MasterState target_ = MasterState::Init;
    MasterState current_ = MasterState::Init;
    bool pending_ = false;  // a request the worker has not picked up yet
    bool running_ = false;  // the worker is running a sequence
    std::optional<SequenceError> last_error_;
    std::vector<bool> present_;

    std::jthread thread_;  // last: starts after everything above exists
};

}  // namespace ecpair::sequencer
