// The supervisor's state machine (see the header for the states). decide()
// first applies what operators asked for and what the links did, then runs
// the current state's step; each step may ask for a role (role_) and move
// to another state through transition(), which logs the reason and keeps it
// for the status.

#include "ecpair/supervisor/supervisor.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "ecpair/arbitration/arbitration_events.hpp"
#include "ecpair/common/log.hpp"

namespace ecpair::supervisor {
namespace {

using arbitration::ArbitrationOutcome;

std::shared_ptr<spdlog::logger> log() { return logger("supervisor"); }

using redundancy::RedState;

std::uint32_t ms(std::chrono::nanoseconds d) {
    return static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(d).count());
}

std::uint64_t as_number(const wire::MacAddress& mac) {
    std::uint64_t v = 0;
    for (const auto b : mac.bytes) v = (v << 8) | b;
    return v;
}

bool is_active_state(SupervisorState s) { return s == SupervisorState::Active || s == SupervisorState::HandingOver; }

template <class Enum>
std::uint32_t code(Enum e) {
    return static_cast<std::uint32_t>(e);
}

// How long a heard CMF header still describes the master that sent it.
constexpr std::chrono::milliseconds kHeardRecently{500};
// How long a switchover asked for at the INACTIVE stays asked for.
constexpr std::uint64_t kSwitchoverRequestCycles = 2000;

}  // namespace

std::string_view to_string(SupervisorState state) {
    switch (state) {
        case SupervisorState::Listening: return "LISTENING";
        case SupervisorState::Standby: return "STANDBY";
        case SupervisorState::HandOffPending: return "HANDOFF_PENDING";
        case SupervisorState::NoActive: return "NO_ACTIVE";
        case SupervisorState::Isolated: return "ISOLATED";
        case SupervisorState::Active: return "ACTIVE";
        case SupervisorState::HandingOver: return "HANDING_OVER";
        case SupervisorState::BackingOff: return "BACKING_OFF";
    }
    return "?";
}

namespace {

// The other master's last frames after a collision: its own detection takes
// collision_cycles, and what it sent meanwhile is still on the way.
std::chrono::nanoseconds settle_time(const SupervisorOptions& options) {
    return (options.collision_cycles + 2) * options.cycle_time;
}

arbitration::ArbiterOptions with_settle_time(const SupervisorOptions& options) {
    auto arbitration = options.arbitration;
    arbitration.settle_time = settle_time(options);
    return arbitration;
}

}  // namespace

Supervisor::Supervisor(const SupervisorOptions& options, arbitration::RandomSource& random, master::EventQueue& events)
    : options_(options),
      events_(events),
      arbiter_(with_settle_time(options), random),
      comm_(options.comm_timeout,
            options.link_loss_confirm.count() > 0 ? options.link_loss_confirm : 3 * options.cycle_time,
            options.cycle_time) {
    status_.comm_timeout = options.comm_timeout;
}

// ---- operator commands (any thread)

Expected<void, std::string> Supervisor::switchover() {
    const auto s = status();
    if (s.forced_standby && s.role == RedState::Inactive) {
        return unexpected(std::string("this member is forced to standby: release it first (unforce-standby)"));
    }
    if (s.state == SupervisorState::HandingOver || s.state == SupervisorState::HandOffPending) {
        return unexpected(std::string(to_string(HandOffRefusal::AlreadyRunning)));
    }
    if (s.role == RedState::Inactive && s.state != SupervisorState::Standby) {
        return unexpected(fmt::format("this member is INACTIVE ({}) and follows no ACTIVE partner it could take over from",
                                      to_string(s.state)));
    }
    if (s.role == RedState::Inactive && !s.hot_standby) {
        return unexpected(std::string(
            "this member is no hot standby (it does not mirror an ACTIVE partner with the same ENI and parameters)"));
    }
    if (s.role == RedState::Active && s.handoff_refusal) {
        return unexpected(fmt::format("switchover refused: {}", to_string(*s.handoff_refusal)));
    }
    switchover_request_.store(true);
    return {};
}

void Supervisor::force_standby(bool forced) { force_request_.store(forced ? 1 : 0); }

void Supervisor::request_role(RedState role) { role_request_.store(static_cast<int>(role)); }

SupervisorStatus Supervisor::status() const {
    std::lock_guard lock(status_mutex_);
    return status_;
}

// ---- helpers

void Supervisor::transition(SupervisorState to, std::string why) {
    log()->warn("cycle {}: supervisor {} -> {}: {}", cycle_, to_string(state_), to_string(to), why);
    state_ = to;
    why_ = std::move(why);
}

void Supervisor::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    events_.push(master::Event{kind, cycle_, std::chrono::system_clock::now(), a, b, c, d});
}

arbitration::Contender Supervisor::ours(const Observation& seen) const {
    return {epoch_, seen.slaves_reached.value_or(0), as_number(seen.member)};
}

std::optional<arbitration::Contender> Supervisor::theirs(const Observation& seen) const {
    if (!seen.heard || seen.now - seen.heard->at > kHeardRecently) return std::nullopt;
    return arbitration::Contender{seen.heard->sender.epoch, seen.heard->sender.slaves_reached,
                                  as_number(seen.heard->sender.member)};
}

bool Supervisor::heard_new_active(const Observation& seen) const { return seen.headers_heard != headers_seen_; }

bool Supervisor::may_take_bus(const Observation& seen) const {
    return !forced_ && (seen.main_link_up || seen.red_link_up);
}

void Supervisor::take_bus(const Observation& seen, std::string why) {
    std::uint32_t newest = epoch_;
    if (seen.heard) newest = std::max(newest, seen.heard->sender.epoch);
    if (seen.partner_status) newest = std::max(newest, seen.partner_status->epoch);
    epoch_ = newest + 1;
    role_ = RedState::Active;
    ++counters_.takeovers;
    partner_seen_ = false;
    returns_reported_ = false;
    foreign_cycles_ = 0;
    handed_over_.reset();
    announcement_.reset();
    pending_handoff_.reset();
    no_active_.reset();
    transition(SupervisorState::Active, fmt::format("{} (epoch {})", why, epoch_));
}

void Supervisor::step_down(SupervisorState to, std::string why) {
    role_ = RedState::Inactive;
    announcement_.reset();
    transition(to, std::move(why));
}

// ---- the cycle

redundancy::RoleDecision Supervisor::decide(const Observation& seen) {
    cycle_ = seen.cycle;
    role_.reset();
    comm_.cycle(seen.now);
    if (state_ == SupervisorState::Standby || state_ == SupervisorState::HandOffPending) {
        // The figure for choosing comm_timeout: only the silence a standby counts
        // (listening at start counts too, but says nothing about the partner).
        longest_standby_silence_ = std::max(longest_standby_silence_, comm_.silence());
    }

    if (!started_) {
        started_ = true;
        links_up_[0] = seen.main_link_up;
        links_up_[1] = seen.red_link_up;
        headers_seen_ = seen.headers_heard;
        if (options_.start_in_forced_standby) {
            forced_ = true;
            raise(events::kStandbyForced, 1);
            no_active_ = NoActiveReason::ForcedStandby;
            transition(SupervisorState::NoActive, "started in forced standby (start_in_forced_standby)");
        } else if (options_.start_active) {
            take_bus(seen, "configured to start ACTIVE");
        } else {
            arbiter_.start(seen.now);
            transition(SupervisorState::Listening, "starting: listening for an ACTIVE master before taking the bus");
        }
    }

    // Operator commands.
    if (const int f = force_request_.exchange(-1); f >= 0 && (f == 1) != forced_) {
        forced_ = f == 1;
        raise(events::kStandbyForced, forced_ ? 1 : 0);
        if (forced_ && is_active_state(state_)) {
            switchover_request_.store(true);  // hand the bus over if the partner can take it
        } else if (forced_ && (state_ == SupervisorState::Listening || state_ == SupervisorState::BackingOff)) {
            no_active_ = NoActiveReason::ForcedStandby;
            transition(SupervisorState::NoActive, "forced to standby while no ACTIVE master is heard");
            raise(events::kNoActiveMaster, code(NoActiveReason::ForcedStandby));
        }
    }
    if (const int r = role_request_.exchange(-1); r >= 0) {
        const auto asked = static_cast<RedState>(r);
        if (asked == RedState::Active && !is_active_state(state_)) {
            if (forced_) {
                log()->warn("cycle {}: operator asks for ACTIVE, refused: forced to standby", cycle_);
            } else {
                take_bus(seen, "the operator asked for ACTIVE");
            }
        } else if (asked == RedState::Inactive && is_active_state(state_)) {
            comm_.reset(seen.now);
            step_down(SupervisorState::Standby, "the operator asked for INACTIVE (no hand-off)");
        }
    }

    watch_links(seen);

    switch (state_) {
        case SupervisorState::Listening: on_listening(seen); break;
        case SupervisorState::Standby: on_standby(seen); break;
        case SupervisorState::HandOffPending: on_handoff_pending(seen); break;
        case SupervisorState::NoActive: on_no_active(seen); break;
        case SupervisorState::Isolated: on_isolated(seen); break;
        case SupervisorState::Active: on_active(seen); break;
        case SupervisorState::HandingOver: on_handing_over(seen); break;
        case SupervisorState::BackingOff: on_backing_off(seen); break;
    }
    // An operator's switchover request is used by the state it is meant for, or forgotten.
    if (switchover_request_.exchange(false) && !is_active_state(state_) && state_ == SupervisorState::Standby) {
        switchover_requested_ = true;
        switchover_until_ = cycle_ + kSwitchoverRequestCycles;
        log()->info("cycle {}: switchover asked at the INACTIVE: asking the ACTIVE partner in the standby status",
                    cycle_);
    }
    if (switchover_requested_ && (state_ != SupervisorState::Standby || cycle_ > switchover_until_)) {
        switchover_requested_ = false;
    }

    headers_seen_ = seen.headers_heard;
    cmfs_seen_ = seen.cmfs_completed;
    answers_seen_ = seen.partner_answers;
    foreign_seen_ = seen.foreign_frames;
    followed_frames_seen_ = seen.followed_master_frames;

    redundancy::RoleDecision decision;
    decision.role = role_;
    decision.epoch = epoch_;
    decision.first_cycle = std::exchange(first_cycle_, std::nullopt);
    if (announcement_) {
        decision.handoff_cycle = announcement_->cycle();
        decision.handoff_committed = announcement_->committed();
    }
    const bool standby = state_ == SupervisorState::Standby || state_ == SupervisorState::HandOffPending;
    decision.ready_for_handoff =
        standby && !forced_ && seen.mirror_fresh && seen.main_link_up && seen.red_link_up;
    decision.forced_standby = forced_;
    decision.switchover_requested = switchover_requested_;
    publish(seen, decision);
    return decision;
}

void Supervisor::watch_links(const Observation& seen) {
    const bool was_up[2] = {links_up_[0], links_up_[1]};
    links_up_[0] = seen.main_link_up;
    links_up_[1] = seen.red_link_up;
    if ((was_up[0] && !links_up_[0]) || (was_up[1] && !links_up_[1])) comm_.link_lost(seen.now);
    if (links_up_[0] || links_up_[1] || state_ == SupervisorState::Isolated) return;
    if (is_active_state(state_)) {
        raise(events::kAllLinksLost, 1);
        step_down(SupervisorState::Isolated, "all links lost: ACTIVE becomes INACTIVE");
    } else {
        raise(events::kAllLinksLost, 0);
        pending_handoff_.reset();
        transition(SupervisorState::Isolated, "all links lost: isolated, will not take over");
    }
    no_active_ = NoActiveReason::Isolated;
}

// ---- INACTIVE states

void Supervisor::on_listening(const Observation& seen) {
    const bool heard = heard_new_active(seen);
    switch (arbiter_.step(seen.now, heard)) {
        case arbitration::Verdict::Wait: return;
        case arbitration::Verdict::Yield:
            raise(arbitration::events::kArbitrationSettled, code(ArbitrationOutcome::YieldedToActive), epoch_,
                  seen.slaves_reached.value_or(0), seen.heard ? seen.heard->sender.slaves_reached : 0xFFFF);
            comm_.reset(seen.now);
            transition(SupervisorState::Standby, "an ACTIVE master is heard: standing by");
            return;
        case arbitration::Verdict::TakeBus:
            if (!may_take_bus(seen)) {
                no_active_ = NoActiveReason::ForcedStandby;
                transition(SupervisorState::NoActive, "no ACTIVE master heard, and this member may not take the bus");
                raise(events::kNoActiveMaster, code(*no_active_));
                return;
            }
            take_bus(seen, "no ACTIVE master heard while listening: taking the bus");
            raise(arbitration::events::kArbitrationSettled, code(ArbitrationOutcome::TookBusAfterListening),
                  epoch_);
            return;
    }
}

void Supervisor::on_standby(const Observation& seen) {
    if (seen.cmfs_completed != cmfs_seen_) {
        comm_.heard(seen.now);
    } else if (heard_new_active(seen) && seen.heard && !seen.heard->same_fingerprint) {
        comm_.heard(seen.now);  // a partner that differs is alive, though never mirrored
    }
    if (seen.heard) epoch_ = std::max(epoch_, seen.heard->sender.epoch);

    // A forced standby never takes a hand-off, even one acknowledged before the force was applied
    // (the acknowledgement is withdrawn with the next CMF; the ACTIVE then cancels).
    if (!forced_ && seen.heard && seen.heard->same_fingerprint && seen.heard->flags.handoff_request &&
        seen.acknowledged_handoff == seen.heard->sender.handoff_cycle) {
        pending_handoff_ = seen.heard->sender.handoff_cycle;
        handoff_committed_ = seen.heard->flags.handoff_committed;
        switchover_requested_ = false;
        transition(SupervisorState::HandOffPending,
                   fmt::format("the ACTIVE hands the bus over at cycle {}: acknowledged", *pending_handoff_));
        return;
    }
    if (comm_.expired()) partner_silent(seen);
}

void Supervisor::partner_silent(const Observation& seen) {
    const bool differs = seen.heard && !seen.heard->same_fingerprint;
    SilenceAction action;
    if (forced_) {
        action = SilenceAction::RefusedForced;
    } else if (differs && !options_.takeover_from_differing_partner) {
        action = SilenceAction::RefusedPartnerDiffers;
    } else {
        action = seen.mirror_fresh ? SilenceAction::TakingOverHot : SilenceAction::TakingOverCold;
    }
    ++counters_.comm_timeouts;
    raise(events::kCommTimeout, ms(comm_.silence()), ms(comm_.timeout()), code(action),
          comm_.shortened() ? 1 : 0);
    const auto silence = fmt::format("partner silent for {} ms (comm timeout {} ms{})", ms(comm_.silence()),
                                     ms(comm_.timeout()), comm_.shortened() ? ", shortened by a link loss" : "");
    pending_handoff_.reset();
    switch (action) {
        case SilenceAction::TakingOverHot:
        case SilenceAction::TakingOverCold:
            takeover_cycle_ = seen.cycle;
            take_bus(seen, silence + (action == SilenceAction::TakingOverHot ? ": taking over hot"
                                                                                     : ": taking over cold"));
            return;
        case SilenceAction::RefusedForced:
            no_active_ = NoActiveReason::ForcedStandby;
            break;
        default:
            no_active_ = NoActiveReason::PartnerDiffers;
            break;
    }
    raise(events::kNoActiveMaster, code(*no_active_));
    transition(SupervisorState::NoActive, silence + ": not taking over");
}

void Supervisor::on_handoff_pending(const Observation& seen) {
    if (seen.cmfs_completed != cmfs_seen_) comm_.heard(seen.now);
    const auto h = *pending_handoff_;
    if (forced_) {
        raise(events::kHandOff, code(HandOffPhase::Cancelled), static_cast<std::uint32_t>(h),
              code(HandOffRefusal::ForcedStandby));
        ++counters_.handoffs_cancelled;
        pending_handoff_.reset();
        transition(SupervisorState::Standby,
                   fmt::format("forced to standby: the hand-off at cycle {} is not taken (the ACTIVE keeps the bus "
                               "unless it has stepped down already)",
                               h));
        return;
    }
    const bool announces_h = seen.heard && seen.heard->same_fingerprint && seen.heard->flags.handoff_request &&
                             seen.heard->sender.handoff_cycle == h;
    if (announces_h && seen.heard->flags.handoff_committed) handoff_committed_ = true;
    // Only an uncommitted hand-off can be withdrawn: once committed, a header
    // without the announcement is an older CMF that arrived late.
    if (!handoff_committed_ && seen.heard && seen.heard->same_fingerprint && !announces_h) {
        raise(events::kHandOff, code(HandOffPhase::Cancelled), static_cast<std::uint32_t>(h),
              code(HandOffRefusal::NotAcknowledged));
        ++counters_.handoffs_cancelled;
        pending_handoff_.reset();
        transition(SupervisorState::Standby, fmt::format("the ACTIVE withdrew the hand-off at cycle {}", h));
        return;
    }
    // Our cycle is H (counted with the ACTIVE's) and the ACTIVE said it
    // committed: it sends nothing from H on. We have its H-2 at least, so only
    // its last CMF is missing (lost or on its way); further behind, the
    // ACTIVE is late (a stall of its machine) and still has cycles to send:
    // our count catches up as they arrive. Not known to be committed (every
    // CMF that said so was lost, or the ACTIVE stalled before reading the
    // acknowledgement): it may have withdrawn the hand-off in a CMF we never
    // got and still hold the bus, so silence is no reason to take it; the
    // comm timeout decides.
    if (seen.cycle >= h && handoff_committed_ && seen.mirrored_cycle + 2 >= h) {
        raise(events::kHandOff, code(HandOffPhase::TakenOver), static_cast<std::uint32_t>(h));
        ++counters_.handoffs;
        if (seen.cycle > h) first_cycle_ = h;  // read "committed" only after our boundary H
        take_bus(seen, fmt::format("switchover: taking over at cycle {} as announced{}{}", h,
                                   seen.mirrored_cycle + 1 >= h ? "" : " (the ACTIVE's last CMF did not arrive)",
                                   seen.cycle > h ? fmt::format(", {} cycle(s) late", seen.cycle - h) : ""));
        handed_over_ = HandedOver{h, seen.now, std::nullopt, false};
        return;
    }
    if (comm_.expired()) partner_silent(seen);
}

void Supervisor::on_no_active(const Observation& seen) {
    if (heard_new_active(seen) && seen.heard && (seen.heard->same_fingerprint || forced_)) {
        no_active_.reset();
        comm_.reset(seen.now);
        transition(SupervisorState::Standby, "an ACTIVE master is heard: standing by");
        return;
    }
    if (!forced_ && no_active_ == NoActiveReason::ForcedStandby) {
        no_active_.reset();
        arbiter_.start(seen.now);
        transition(SupervisorState::Listening, "released from forced standby: listening before taking the bus");
    }
}

void Supervisor::on_isolated(const Observation& seen) {
    if (!seen.main_link_up && !seen.red_link_up) return;
    raise(events::kLinksRestored);
    no_active_.reset();
    if (forced_) {
        no_active_ = NoActiveReason::ForcedStandby;
        transition(SupervisorState::NoActive, "a link is back; forced to standby");
        return;
    }
    arbiter_.start(seen.now);
    transition(SupervisorState::Listening, "a link is back: listening for an ACTIVE master");
}

// ---- ACTIVE states

void Supervisor::watch_partner(const Observation& seen) {
    if (seen.partner_answers != answers_seen_) {
        if (!partner_seen_) {
            const auto silent_for = seen.partner_last_answer && partner_lost_at_
                                        ? ms(*seen.partner_last_answer - *partner_lost_at_)
                                        : 0;
            raise(events::kPartnerFound, silent_for);
            log()->info("cycle {}: partner {} answers in the CMF", cycle_,
                        seen.partner_status ? seen.partner_status->member.to_string() : std::string("?"));
        }
        partner_seen_ = true;
        return;
    }
    if (partner_seen_ && seen.partner_last_answer && seen.now - *seen.partner_last_answer > options_.partner_silence) {
        partner_seen_ = false;
        partner_lost_at_ = *seen.partner_last_answer;
        ++counters_.partner_lost;
        raise(events::kPartnerLost, ms(seen.now - *seen.partner_last_answer));
    }
}

void Supervisor::watch_returns(const Observation& seen) {
    if (!returns_reported_ && seen.cycles_without_return >= options_.no_return_cycles) {
        returns_reported_ = true;
        const bool after_failover = takeover_cycle_ != 0 && seen.cycle - takeover_cycle_ < 10 * seen.cycles_without_return;
        raise(events::kFramesNotReturning, static_cast<std::uint32_t>(seen.cycles_without_return),
              after_failover ? 1 : 0);
    } else if (returns_reported_ && seen.cycles_without_return == 0) {
        returns_reported_ = false;
        raise(events::kFramesReturning, static_cast<std::uint32_t>(seen.cycle - takeover_cycle_));
    }
}

bool Supervisor::collision_seen(const Observation& seen) {
    const auto foreign = seen.foreign_frames - foreign_seen_;
    const bool only_previous_active = foreign == seen.followed_master_frames - followed_frames_seen_;
    bool counts = foreign != 0;
    if (previous_active_finishing(seen) && counts && only_previous_active) {
        counts = false;
        if (!std::exchange(handed_over_->reported, true)) {
            // Common (its H-1 is often on its way at our boundary H): not an operator's matter.
            log()->debug("cycle {}: frames of the master that handed the bus over at cycle {} still arrive (its last "
                         "cycles, on their way or sent late): not counted as a collision",
                         cycle_, handed_over_->cycle);
        }
    }
    foreign_cycles_ = counts ? foreign_cycles_ + 1 : 0;
    return foreign_cycles_ >= options_.collision_cycles;
}

// The master that handed the bus over at H sends until its own boundary H:
// when it ran late (a stall), its last cycles reach us after our first ones.
// Its frames are no collision while it may still be finishing: until it
// answers as our standby, and a collision's settle time more for frames on
// their way, at most comm_timeout after H. A CMF of it numbering H or later
// says it did not stop: that is a collision like any other.
bool Supervisor::previous_active_finishing(const Observation& seen) {
    if (!handed_over_) return false;
    auto& h = *handed_over_;
    if (!h.answered_at && seen.partner_answers != answers_seen_) h.answered_at = seen.now;
    const bool numbers_ours = seen.headers_heard != headers_seen_ && seen.heard && seen.heard->cycle >= h.cycle;
    auto until = h.at + options_.comm_timeout;
    if (h.answered_at) until = std::min(until, *h.answered_at + settle_time(options_));
    if (numbers_ours || seen.now > until) {
        handed_over_.reset();
        return false;
    }
    return true;
}

std::optional<HandOffRefusal> Supervisor::refusal(const Observation& seen) const {
    std::optional<std::chrono::nanoseconds> age;
    if (seen.partner_last_answer) age = seen.now - *seen.partner_last_answer;
    return handoff_refusal(seen.partner_status, age, options_.partner_silence);
}

void Supervisor::start_handoff(const Observation& seen) {
    if (const auto refused = refusal(seen)) {
        raise(events::kHandOff, code(HandOffPhase::Refused), 0, code(*refused));
        if (forced_) step_down_forced(to_string(*refused));
        return;
    }
    announcement_.emplace(seen.cycle + options_.handoff_lead_cycles);
    raise(events::kHandOff, code(HandOffPhase::Announced),
          static_cast<std::uint32_t>(announcement_->cycle()));
    transition(SupervisorState::HandingOver,
               fmt::format("switchover: handing the bus to the partner at cycle {}", announcement_->cycle()));
}

void Supervisor::on_active(const Observation& seen) {
    watch_partner(seen);
    watch_returns(seen);
    if (collision_seen(seen)) {
        const auto& round = arbiter_.collision(seen.now, ours(seen), theirs(seen));
        ++counters_.collisions;
        raise(arbitration::events::kCollision, round.number,
              static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::microseconds>(round.backoff).count()),
              code(round.kind), code(round.decided_by));
        step_down(SupervisorState::BackingOff,
                  fmt::format("collision with another master (round {}): stopped sending, backing off", round.number));
        return;
    }
    const bool partner_asks = seen.partner_status && seen.partner_status->switchover_requested &&
                              seen.partner_answers != answers_seen_ && !partner_asked_;
    partner_asked_ = seen.partner_status && seen.partner_status->switchover_requested;
    if (switchover_request_.exchange(false) || partner_asks) start_handoff(seen);
}

void Supervisor::on_handing_over(const Observation& seen) {
    watch_partner(seen);
    // Committed is irrevocable (the partner may take over at H on the strength
    // of it): a partner lost now, or a stall of ours, still ends in the step-down.
    if (!partner_seen_ && !announcement_->committed()) {
        raise(events::kHandOff, code(HandOffPhase::Cancelled),
              static_cast<std::uint32_t>(announcement_->cycle()), code(HandOffRefusal::PartnerLost));
        ++counters_.handoffs_cancelled;
        announcement_.reset();
        transition(SupervisorState::Active, "switchover cancelled: the partner went silent");
        if (forced_) step_down_forced("the partner went silent");
        return;
    }
    switch (announcement_->step(seen.cycle, seen.partner_status)) {
        case HandOffAnnouncement::Step::Announce: return;
        case HandOffAnnouncement::Step::Acknowledged:
            raise(events::kHandOff, code(HandOffPhase::Acknowledged),
                  static_cast<std::uint32_t>(announcement_->cycle()));
            return;
        case HandOffAnnouncement::Step::StepDown: {
            const auto h = announcement_->cycle();
            raise(events::kHandOff, code(HandOffPhase::SteppedDown), static_cast<std::uint32_t>(h));
            ++counters_.handoffs;
            comm_.reset(seen.now);
            step_down(SupervisorState::Standby,
                      fmt::format("switchover: last cycle {} sent, the partner takes over at cycle {}", h - 1, h));
            if (forced_) no_active_.reset();
            return;
        }
        case HandOffAnnouncement::Step::Cancel:
            raise(events::kHandOff, code(HandOffPhase::Cancelled),
                  static_cast<std::uint32_t>(announcement_->cycle()), code(HandOffRefusal::NotAcknowledged));
            ++counters_.handoffs_cancelled;
            announcement_.reset();
            transition(SupervisorState::Active, "switchover cancelled: the partner did not acknowledge in time");
            if (forced_) step_down_forced("the partner did not take the bus over");
            return;
    }
}

void Supervisor::step_down_forced(std::string_view why) {
    no_active_ = NoActiveReason::ForcedStandby;
    step_down(SupervisorState::NoActive, fmt::format("forced to standby, and no hot standby can take the bus ({}): "
                                                     "stepping down",
                                                     why));
    raise(events::kNoActiveMaster, code(*no_active_));
}

void Supervisor::on_backing_off(const Observation& seen) {
    switch (arbiter_.step(seen.now, heard_new_active(seen))) {
        case arbitration::Verdict::Wait: return;
        case arbitration::Verdict::Yield:
            ++counters_.backoffs_lost;
            raise(arbitration::events::kArbitrationSettled, code(ArbitrationOutcome::YieldedToActive), epoch_,
                  seen.slaves_reached.value_or(0), seen.heard ? seen.heard->sender.slaves_reached : 0xFFFF);
            comm_.reset(seen.now);
            transition(SupervisorState::Standby, "after the collision the other master holds the bus: standing by");
            return;
        case arbitration::Verdict::TakeBus: {
            ++counters_.backoffs_won;
            const auto other = theirs(seen);
            take_bus(seen, "backoff over and no ACTIVE master heard: taking the bus back");
            raise(arbitration::events::kArbitrationSettled, code(ArbitrationOutcome::KeptBusAfterCollision), epoch_,
                  seen.slaves_reached.value_or(0), other ? other->slaves_reached : 0xFFFF);
            return;
        }
    }
}

void Supervisor::publish(const Observation& seen, const redundancy::RoleDecision& decision) {
    std::lock_guard lock(status_mutex_);
    status_.state = state_;
    if (status_.why != why_) status_.why = why_;
    status_.role = decision.role.value_or(seen.role);
    status_.forced_standby = forced_;
    status_.hot_standby = !is_active_state(state_) && seen.mirror_fresh;
    status_.epoch = epoch_;
    status_.arbitration = arbiter_.state();
    status_.silence = is_active_state(state_) ? std::chrono::nanoseconds(0) : comm_.silence();
    status_.longest_silence = longest_standby_silence_;
    status_.handoff_cycle = announcement_ ? std::optional<std::uint64_t>(announcement_->cycle()) : pending_handoff_;
    status_.no_active = no_active_;
    status_.handoff_refusal = is_active_state(state_) ? refusal(seen) : std::nullopt;
    status_.counters = counters_;
}

}  // namespace ecpair::supervisor
