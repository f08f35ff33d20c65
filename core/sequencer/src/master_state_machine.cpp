// The worker of the master state machine (see the header). The worker
// owns the runners and the position shifts; the mutex guards only what
// other threads read (target, current state, last error, presence). The
// slaves' mailboxes guard themselves (one conversation at a time).

#include "ecpair/sequencer/master_state_machine.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sequencer/identification_update.hpp"
#include "ecpair/sequencer/state_rollback.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint32_t kMasterIndex = 0xFFFF;  // TransitionFailed's "no slave"
constexpr std::uint8_t kErrorAcknowledge = 0x10;

std::string transition_name(eni::Transition t) {
    return fmt::format("{} ({} -> {})", eni::to_string(t), eni::to_string(eni::from_state(t)),
                       eni::to_string(eni::to_state(t)));
}

std::optional<SequenceFailure> quiet_failure(std::optional<bus::BusErrc> code) {
    if (code == bus::BusErrc::MasterRedStateInactive) return SequenceFailure::MasterInactive;
    if (code == bus::BusErrc::Cancelled) return SequenceFailure::Cancelled;
    return std::nullopt;
}

bool is_quiet(SequenceFailure f) {
    return f == SequenceFailure::MasterInactive || f == SequenceFailure::Cancelled || f == SequenceFailure::Stopped;
}

}  // namespace

std::string_view to_string(SequenceFailure failure) {
    switch (failure) {
        case SequenceFailure::BusMismatch: return "bus mismatch";
        case SequenceFailure::ScanFailed: return "scan failed";
        case SequenceFailure::InitCmd: return "InitCmd failed";
        case SequenceFailure::MailboxInitCmd: return "mailbox InitCmd failed";
        case SequenceFailure::CyclicStateNotApplied: return "cyclic state not applied";
        case SequenceFailure::MasterInactive: return "master is INACTIVE";
        case SequenceFailure::Cancelled: return "cancelled";
        case SequenceFailure::Stopped: return "stopped";
    }
    return "?";
}

MasterStateMachine::MasterStateMachine(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus,
                                       StateMachineHooks hooks, master::EventQueue* events, Clock& clock,
                                       StateMachineOptions options)
    : eni_(std::move(eni)),
      bus_(bus),
      hooks_(std::move(hooks)),
      events_(events),
      clock_(clock),
      options_(options),
      init_cmds_(bus, clock, options.init_cmds),
      own_mailboxes_(options.mailboxes ? nullptr : std::make_unique<SlaveMailboxes>(*eni_, bus, clock)),
      mailboxes_(options.mailboxes ? *options.mailboxes : *own_mailboxes_),
      mailbox_init_cmds_(clock),
      position_shift_(eni_->slaves.size(), 0),
      present_(eni_->slaves.size(), true),
      thread_([this](std::stop_token stop) { worker(stop); }) {}

MasterStateMachine::~MasterStateMachine() {
    thread_.request_stop();
    changed_.notify_all();
}

void MasterStateMachine::request(MasterState target) {
    {
        std::lock_guard lock(mutex_);
        target_ = target;
        pending_ = true;
    }
    logger("sequencer")->info("master state {} requested", to_string(target));
    changed_.notify_all();
}

void MasterStateMachine::adopt(MasterState state) {
    {
        std::lock_guard lock(mutex_);
        current_ = state;
        target_ = state;
        pending_ = false;
        last_error_.reset();
    }
    logger("sequencer")->info("master state {} adopted (the slaves are already there)", to_string(state));
    changed_.notify_all();
}

MasterState MasterStateMachine::target() const {
    std::lock_guard lock(mutex_);
    return target_;
}

MasterState MasterStateMachine::current() const {
    std::lock_guard lock(mutex_);
    return current_;
}

bool MasterStateMachine::busy() const {
    std::lock_guard lock(mutex_);
    return pending_ || running_;
}

std::optional<SequenceError> MasterStateMachine::last_error() const {
    std::lock_guard lock(mutex_);
    return last_error_;
}

std::vector<bool> MasterStateMachine::presence() const {
    std::lock_guard lock(mutex_);
    return present_;
}

std::vector<std::uint16_t> MasterStateMachine::position_shift() const {
    std::lock_guard lock(mutex_);
    return position_shift_;
}

void MasterStateMachine::update_presence(std::vector<bool> present, std::vector<std::uint16_t> position_shift) {
    std::lock_guard lock(mutex_);
    if (present.size() == present_.size()) present_ = std::move(present);
    if (position_shift.size() == position_shift_.size()) position_shift_ = std::move(position_shift);
}

bool MasterStateMachine::wait_idle(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [this] { return !pending_ && !running_; });
}

void MasterStateMachine::worker(std::stop_token stop) {
    std::unique_lock lock(mutex_);
    for (;;) {
        changed_.wait(lock, stop, [this] { return pending_; });
        if (stop.stop_requested()) return;
        running_ = true;
        last_error_.reset();
        if (hooks_.on_start) {
            lock.unlock();
            hooks_.on_start();
            lock.lock();
        }
        std::optional<SequenceError> error;
        MasterState target{};
        for (;;) {
            // Re-read the target at every state boundary: a new request redirects the sequence.
            target = target_;
            pending_ = false;
            const auto transition = next_transition(current_, target, *eni_);
            if (!transition) break;
            lock.unlock();
            error = run_transition(*transition, stop);
            lock.lock();
            if (error) break;
            current_ = *transition_target(*transition);
        }
        lock.unlock();
        finish(target, std::move(error));
        lock.lock();
    }
}

void MasterStateMachine::finish(MasterState target, std::optional<SequenceError> error) {
    SequenceResult result;
    result.target = target;
    result.error = error;
    {
        std::lock_guard lock(mutex_);
        result.reached = current_;
        last_error_ = std::move(error);
    }
    const bool stopped = result.error && result.error->failure == SequenceFailure::Stopped;
    if (!result.error) logger("sequencer")->info("master state {} reached", to_string(result.reached));
    // The callback runs before the machine counts as idle, so wait_idle() also waits for it.
    if (!stopped && hooks_.on_done) hooks_.on_done(result);
    {
        std::lock_guard lock(mutex_);
        running_ = false;
    }
    changed_.notify_all();
}

std::optional<SequenceError> MasterStateMachine::run_transition(eni::Transition t, std::stop_token stop) {
    const auto from = *transition_source(t);
    const auto to = *transition_target(t);
    auto log = logger("sequencer");
    log->info("transition {} started", transition_name(t));
    const auto started = clock_.now();

    auto error = [&]() -> std::optional<SequenceError> {
        if (t == eni::Transition::IP) {
            if (auto e = startup_scan(stop)) return e;
        }
        const bool going_down = static_cast<int>(to) < static_cast<int>(from);
        if (going_down) {
            if (auto e = apply_cyclic_state(to, t, stop)) return e;
        }
        const auto plan = plan_transition(*eni_, t, presence());
        if (!going_down && t != eni::Transition::IP) {
            if (auto e = take_back_slaves_ahead_of(from, plan, t, stop)) return e;
        }
        CommandContext master_context;
        for (const auto& cmd : plan.master_before) {
            if (auto r = init_cmds_.run(cmd, master_context, stop); !r) return from_init_cmd(r.error(), t);
        }
        for (const auto& slave : plan.slaves) {
            if (auto e = run_slave(slave, t, stop)) return e;
        }
        for (const auto& cmd : plan.master_after) {
            if (auto r = init_cmds_.run(cmd, master_context, stop); !r) return from_init_cmd(r.error(), t);
        }
        if (!going_down) {
            if (auto e = apply_cyclic_state(to, t, stop)) return e;
        }
        return std::nullopt;
    }();

    const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(clock_.now() - started).count();
    if (!error) {
        log->info("transition {} done in {} ms", transition_name(t), elapsed);
        return std::nullopt;
    }
    if (is_quiet(error->failure)) {
        log->warn("transition {} stopped after {} ms: {}", transition_name(t), elapsed, error->message);
    } else {
        log->error("transition {} failed after {} ms: {}", transition_name(t), elapsed, error->message);
        raise(master::events::kTransitionFailed, static_cast<std::uint32_t>(eni::from_state(t)),
              static_cast<std::uint32_t>(eni::to_state(t)),
              error->slave_index ? static_cast<std::uint32_t>(*error->slave_index) : kMasterIndex);
    }
    return error;
}

std::optional<SequenceError> MasterStateMachine::take_back_slaves_ahead_of(MasterState state, const TransitionPlan& plan,
                                                                          eni::Transition t, std::stop_token stop) {
    std::vector<std::pair<std::size_t, std::uint16_t>> stations;
    for (const auto& slave : plan.slaves) stations.emplace_back(slave.slave_index, eni_->slaves[slave.slave_index].info.phys_addr);
    const auto wanted = static_cast<std::uint8_t>(to_slave_state(state));
    auto taken = take_back_slaves_ahead(bus_, clock_, stations, wanted, options_.cyclic_state_timeout, stop);
    if (!taken) {
        return SequenceError{SequenceFailure::InitCmd, *transition_source(t), *transition_target(t), std::nullopt,
                             fmt::format("transition {}: taking slaves back to {} first: {}", eni::to_string(t),
                                         to_string(state), taken.error())};
    }
    for (const auto& slave : *taken) {
        logger("sequencer")->warn("slave '{}' (station {}) was in {}, ahead of the master's {} (an earlier {} stopped "
                                  "halfway): back to {} before {} runs again",
                                  eni_->slaves[slave.slave_index].info.name, slave.station,
                                  wire::al_state_name(slave.state), to_string(state), eni::to_string(t),
                                  to_string(state), eni::to_string(t));
    }
    return std::nullopt;
}

std::optional<SequenceError> MasterStateMachine::startup_scan(std::stop_token stop) {
    auto outcome = StartupScan(bus_, clock_).run(*eni_, stop);
    if (!outcome) {
        const auto quiet = quiet_failure(outcome.error().code);
        return SequenceError{quiet.value_or(SequenceFailure::ScanFailed), MasterState::Init, MasterState::Preop,
                             std::nullopt, "startup scan: " + outcome.error().message};
    }
    raise(master::events::kBusScanStatus, outcome->report.responding,
          static_cast<std::uint32_t>(eni_->slaves.size()), outcome->matches ? 1 : 0);
    for (const auto& c : outcome->comparisons) {
        if (c.configured_index) {
            const bool found = c.match != bus::SlaveMatch::Missing && c.match != bus::SlaveMatch::Absent;
            raise(master::events::kSlavePresence, static_cast<std::uint32_t>(*c.configured_index), found ? 1 : 0);
        }
        if (c.is_mismatch()) raise(master::events::kBusMismatch, c.position, static_cast<std::uint32_t>(c.match));
    }
    {
        std::lock_guard lock(mutex_);
        present_ = outcome->present;
        position_shift_ = outcome->position_shift;
    }
    if (hooks_.on_scan) hooks_.on_scan(*outcome);
    if (outcome->matches) return std::nullopt;

    const auto mismatches = outcome->mismatches();
    std::string message = "bus mismatch: " + mismatches.front()->describe();
    if (mismatches.size() > 1) message += fmt::format(" (and {} more)", mismatches.size() - 1);
    return SequenceError{SequenceFailure::BusMismatch, MasterState::Init, MasterState::Preop,
                         mismatches.front()->configured_index, std::move(message)};
}

std::optional<SequenceError> MasterStateMachine::run_slave(const SlavePlan& plan, eni::Transition t,
                                                           std::stop_token stop, bool may_recover) {
    acknowledge_error(plan.slave_index, t);
    const auto context = context_for(plan.slave_index);
    if (plan.synthesized) {
        logger("sequencer")->debug("{}: no ESC InitCmds in the ENI, running made-up ones", context.describe());
    }
    for (const auto& step : plan.steps) {
        if (const auto* cmd = std::get_if<eni::EcatCmd>(&step)) {
            if (auto r = init_cmds_.run(*cmd, context, stop); !r) {
                if (may_recover && t == eni::Transition::PS && is_identification_update(r.error())) {
                    return recover_identification_update(plan, t, stop);
                }
                return from_init_cmd(r.error(), t);
            }
            continue;
        }
        if (auto r = mailbox_init_cmds_.run(mailboxes_.find(plan.slave_index), step, context.describe(), stop); !r) {
            auto failure = quiet_failure(r.error().bus_error).value_or(SequenceFailure::MailboxInitCmd);
            if (r.error().stopped) failure = SequenceFailure::Stopped;
            return SequenceError{failure, *transition_source(t), *transition_target(t), plan.slave_index,
                                 fmt::format("transition {}: {}", eni::to_string(t), r.error().describe())};
        }
    }
    return std::nullopt;
}

// ETG.1020: the slave took its ID selector as its station alias and refused
// SAFEOP with 0x0061. It goes through INIT, its identification is checked
// against the alias it shows now, and INIT -> PREOP -> SAFEOP runs again for it.
std::optional<SequenceError> MasterStateMachine::recover_identification_update(const SlavePlan& plan, eni::Transition t,
                                                                               std::stop_token stop) {
    const auto& slave = eni_->slaves[plan.slave_index];
    auto log = logger("sequencer");
    log->warn("slave '{}' (station {}): AL status code 0x0061 (device identification value updated, ETG.1020): "
              "taking it through INIT",
              slave.info.name, slave.info.phys_addr);
    const auto alias = reinitialise_after_identification_update(
        bus_, clock_, bus::SlaveAddress::station(slave.info.phys_addr), options_.cyclic_state_timeout, stop);
    if (!alias) {
        return SequenceError{SequenceFailure::InitCmd, *transition_source(t), *transition_target(t), plan.slave_index,
                             fmt::format("transition {}: slave '{}': recovering from 0x0061: {}", eni::to_string(t),
                                         slave.info.name, alias.error())};
    }
    raise(master::events::kSlaveIdentificationUpdated, static_cast<std::uint32_t>(plan.slave_index), *alias);
    const auto& id = slave.info.identification;
    if (id && id->enabled && id->ado == bus::kIdentificationAlias && id->value && *id->value != 0 && *id->value != *alias) {
        return SequenceError{SequenceFailure::BusMismatch, *transition_source(t), *transition_target(t),
                             plan.slave_index,
                             fmt::format("slave '{}' (station {}) now identifies as station alias {}, the ENI expects {}",
                                         slave.info.name, slave.info.phys_addr, *alias, *id->value)};
    }
    log->info("slave '{}' (station {}): station alias {} now; INIT -> PREOP -> SAFEOP again", slave.info.name,
              slave.info.phys_addr, *alias);
    std::vector<bool> only(eni_->slaves.size(), false);
    only[plan.slave_index] = true;
    const auto again = plan_transition(*eni_, eni::Transition::IP, only);
    for (const auto& step : again.slaves) {
        if (auto e = run_slave(step, eni::Transition::IP, stop, false)) return e;
    }
    return run_slave(plan, t, stop, false);
}

void MasterStateMachine::acknowledge_error(std::size_t slave_index, eni::Transition t) {
    const auto& slave = eni_->slaves[slave_index];
    // Before IP the station address may not be set yet (masters clear it): address by position then.
    const auto address =
        t == eni::Transition::IP
            ? bus::SlaveAddress::position(static_cast<std::uint16_t>(slave.info.ring_position - position_shift()[slave_index]))
            : bus::SlaveAddress::station(slave.info.phys_addr);
    auto status = bus::read_register(bus_, address, wire::reg::kAlStatus, 6);
    if (!status || status->wkc != 1 || status->data.size() < 6) return;
    const wire::AlStatus al{status->data[0]};
    if (!al.error()) return;
    const auto code = load_le<std::uint16_t>(status->data, 4);
    logger("sequencer")->warn("slave '{}' (station {}) is in {} with AL status code 0x{:04x} ({}): acknowledging",
                              slave.info.name, slave.info.phys_addr, al.to_string(), code,
                              wire::al_status_code_text(code));
    raise(master::events::kSlaveStateError, static_cast<std::uint32_t>(slave_index), al.raw, code);
    (void)bus::write_register(bus_, address, wire::reg::kAlControl,
                              {static_cast<std::uint8_t>(al.state() | kErrorAcknowledge), 0});
}

std::optional<SequenceError> MasterStateMachine::apply_cyclic_state(MasterState state, eni::Transition t,
                                                                    std::stop_token stop) {
    if (!hooks_.request_cyclic_state) return std::nullopt;
    const auto wanted = to_slave_state(state);
    hooks_.request_cyclic_state(wanted);
    if (!hooks_.cyclic_state) return std::nullopt;
    const auto deadline = clock_.now() + options_.cyclic_state_timeout;
    while (hooks_.cyclic_state() != wanted) {
        if (stop.stop_requested()) {
            return SequenceError{SequenceFailure::Stopped, *transition_source(t), *transition_target(t), std::nullopt,
                                 "stopped"};
        }
        if (clock_.now() >= deadline) {
            return SequenceError{SequenceFailure::CyclicStateNotApplied, *transition_source(t), *transition_target(t),
                                 std::nullopt,
                                 fmt::format("transition {}: the cyclic master did not apply {} within {} ms",
                                             eni::to_string(t), to_string(state),
                                             options_.cyclic_state_timeout.count())};
        }
        clock_.sleep_for(kPollInterval, stop);
    }
    return std::nullopt;
}

CommandContext MasterStateMachine::context_for(std::size_t slave_index) const {
    const auto& slave = eni_->slaves[slave_index];
    CommandContext context;
    context.owner = slave.info.name;
    context.station = slave.info.phys_addr;
    context.slave_index = slave_index;
    {
        std::lock_guard lock(mutex_);
        context.position_shift = position_shift_[slave_index];
    }
    context.dc = dc::start_time_parameters(*eni_, slave_index, presence());
    return context;
}

void MasterStateMachine::continue_mailbox_counters(const std::vector<std::uint8_t>& last_counters) {
    mailboxes_.continue_after(last_counters);
}

SequenceError MasterStateMachine::from_init_cmd(const InitCmdError& error, eni::Transition t) const {
    auto failure = quiet_failure(error.bus_error).value_or(SequenceFailure::InitCmd);
    if (error.failure == InitCmdFailure::Stopped) failure = SequenceFailure::Stopped;
    return SequenceError{failure, *transition_source(t), *transition_target(t), error.slave_index,
                         fmt::format("transition {}: {}", eni::to_string(t), error.describe())};
}

void MasterStateMachine::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (events_) events_->raise(kind, a, b, c);
}

}  // namespace ecpair::sequencer
