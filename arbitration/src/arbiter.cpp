#include "ecpair/arbitration/arbiter.hpp"

#include <fmt/format.h>

#include "ecpair/common/log.hpp"

namespace ecpair::arbitration {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("arbitration"); }

double ms(std::chrono::nanoseconds d) { return static_cast<double>(d.count()) / 1e6; }

}  // namespace

std::string_view to_string(ArbiterState state) {
    switch (state) {
        case ArbiterState::Idle: return "IDLE";
        case ArbiterState::Listening: return "LISTENING";
        case ArbiterState::BackingOff: return "BACKING_OFF";
    }
    return "?";
}

std::string_view to_string(BackoffKind kind) {
    switch (kind) {
        case BackoffKind::Random: return "random";
        case BackoffKind::Preferred: return "preferred";
        case BackoffKind::Deferring: return "deferring";
    }
    return "?";
}

Arbiter::Arbiter(const ArbiterOptions& options, RandomSource& random) : options_(options), random_(random) {}

void Arbiter::transition(ArbiterState to, std::string_view why) {
    log()->info("arbitration {} -> {}: {}", to_string(state_), to_string(to), why);
    state_ = to;
}

void Arbiter::start(TimePoint now) {
    const auto jitter = random_.between(std::chrono::nanoseconds(0), options_.backoff_max);
    deadline_ = now + options_.listen_time + jitter;
    transition(ArbiterState::Listening,
               fmt::format("listening {:.1f} ms for an ACTIVE master before taking the bus", ms(options_.listen_time + jitter)));
}

const CollisionRound& Arbiter::collision(TimePoint now, const Contender& ours, const std::optional<Contender>& theirs) {
    ++collisions_;
    const bool repeat = last_settled_ && now - *last_settled_ <= options_.repeat_window;
    round_.number = repeat ? round_.number + 1 : 1;

    Comparison decision;
    if (theirs) decision = round_.number >= 2 ? compare(ours, *theirs) : compare_reach(ours, *theirs);
    switch (decision.preference) {
        case Preference::Ours:
            round_.kind = BackoffKind::Preferred;
            round_.backoff = options_.backoff_min;
            break;
        case Preference::Theirs:
            round_.kind = BackoffKind::Deferring;
            round_.backoff = 2 * options_.backoff_max;
            break;
        case Preference::Undecided:
            round_.kind = BackoffKind::Random;
            round_.backoff = random_.between(options_.backoff_min, options_.backoff_max);
            break;
    }
    round_.decided_by = decision.decided_by;
    round_.backoff += options_.settle_time;
    deadline_ = now + round_.backoff;
    deaf_until_ = now + options_.settle_time;
    transition(ArbiterState::BackingOff,
               fmt::format("collision round {}: stop sending, back off {:.1f} ms ({}{}{})", round_.number,
                           ms(round_.backoff), to_string(round_.kind),
                           round_.kind == BackoffKind::Random ? "" : ": ",
                           round_.kind == BackoffKind::Random ? std::string_view() : to_string(round_.decided_by)));
    return round_;
}

Verdict Arbiter::step(TimePoint now, bool active_heard) {
    if (state_ == ArbiterState::Idle) return Verdict::Wait;
    const bool counts = state_ == ArbiterState::Listening || now >= deaf_until_;
    if (active_heard && counts) {
        last_settled_ = now;
        transition(ArbiterState::Idle, "an ACTIVE master is heard: yield and stand by");
        return Verdict::Yield;
    }
    if (now < deadline_) return Verdict::Wait;
    last_settled_ = now;
    transition(ArbiterState::Idle, state_ == ArbiterState::Listening ? "no ACTIVE master heard: take the bus"
                                                                     : "backoff over, no ACTIVE master heard: take the bus");
    return Verdict::TakeBus;
}

}  // namespace ecpair::arbitration
