#pragma once
// Who may take the bus (design.md: "each instance has a supervisor that ...
// resolves collisions through random-backoff arbitration on
// FOREIGN_SRC_MAC"). The Arbiter is engaged in two situations and decides,
// cycle by cycle, when its master may send again:
//
//   start-up   LISTENING: the master sends nothing for listen_time plus a
//              random jitter of up to backoff_max. An ACTIVE heard meanwhile
//              (its Cyclic Master Red Frame) -> YIELD: become its standby.
//              Silence -> TAKE_BUS. (A master coming back after a failure
//              thus comes back INACTIVE and never preempts a healthy ACTIVE.)
//   collision  the master is ACTIVE and another master sends too (a foreign
//              source MAC, or another ACTIVE's CMF): BACKING_OFF: stop
//              sending at the next cycle boundary and wait; an ACTIVE heard
//              meanwhile -> YIELD; the wait over in silence -> TAKE_BUS.
//              Every wait begins with settle_time in which nothing heard
//              counts: the other master may still be sending until its own
//              collision detection stops it, and its frames already on the
//              way arrive after that. Were they taken for a master that took
//              the bus back, both could yield and leave the bus to nobody;
//              were the bus taken back while they arrive, that would be
//              another collision.
//
// How long a collision's wait is after settle_time, per round (a collision
// within repeat_window of the last one that settled is the next round):
//   - both reach different numbers of slaves (a repaired double line break):
//     decided at once by the rule in contender.hpp: the preferred master
//     waits backoff_min, the other twice backoff_max, so the bigger half keeps
//     its slaves and the other half's slaves join it;
//   - round 1 otherwise: a random time in [backoff_min, backoff_max];
//   - round 2 and later: the full rule (reach, older epoch, lower MAC).
// Both masters see each other's claims in the CMF, so they agree on the
// rule's outcome: with both CMFs heard the pair settles within two rounds.
// A foreign master that sends no CMF leaves only the random backoff.
//
// Pure logic: the time comes in with every call, randomness from the
// injected RandomSource; every transition is logged.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

#include "ecpair/arbitration/contender.hpp"
#include "ecpair/arbitration/random_source.hpp"

namespace ecpair::arbitration {

using TimePoint = std::chrono::steady_clock::time_point;

struct ArbiterOptions {
    std::chrono::nanoseconds listen_time{std::chrono::milliseconds(200)};
    std::chrono::nanoseconds backoff_min{std::chrono::milliseconds(1)};
    std::chrono::nanoseconds backoff_max{std::chrono::milliseconds(10)};
    // A collision this soon after the last round settled is the next round.
    std::chrono::nanoseconds repeat_window{std::chrono::seconds(2)};
    // After a collision, what is heard this long is the other master's last
    // frames, not a master that took the bus back (see above).
    std::chrono::nanoseconds settle_time{std::chrono::milliseconds(5)};
};

enum class ArbiterState : std::uint8_t { Idle, Listening, BackingOff };
std::string_view to_string(ArbiterState state);

enum class Verdict : std::uint8_t {
    Wait,     // send nothing yet
    TakeBus,  // become ACTIVE
    Yield,    // another master is ACTIVE: become its standby
};

// How one collision round chose its wait.
enum class BackoffKind : std::uint8_t {
    Random,     // drawn from [backoff_min, backoff_max]
    Preferred,  // the rule prefers this master: backoff_min
    Deferring,  // the rule prefers the other: twice backoff_max
};
std::string_view to_string(BackoffKind kind);

struct CollisionRound {
    std::uint32_t number = 0;  // 1 for a first collision
    BackoffKind kind = BackoffKind::Random;
    DecidedBy decided_by = DecidedBy::Nothing;  // with Preferred / Deferring
    std::chrono::nanoseconds backoff{0};  // the whole wait, settle_time included
};

class Arbiter {
public:
    Arbiter(const ArbiterOptions& options, RandomSource& random);

    ArbiterState state() const { return state_; }
    const ArbiterOptions& options() const { return options_; }

    // Start-up: listen before taking the bus.
    void start(TimePoint now);
    // A collision while ACTIVE; `theirs` when the other master's CMF was read.
    const CollisionRound& collision(TimePoint now, const Contender& ours, const std::optional<Contender>& theirs);
    // Every cycle while engaged (state() != Idle). `active_heard`: an ACTIVE
    // master's CMF arrived since the last call. TakeBus and Yield end the
    // engagement (state() is Idle again).
    Verdict step(TimePoint now, bool active_heard);

    // When the current wait ends (engaged only).
    TimePoint deadline() const { return deadline_; }
    const CollisionRound& last_round() const { return round_; }
    std::uint64_t collisions() const { return collisions_; }

private:
    void transition(ArbiterState to, std::string_view why);

    ArbiterOptions options_;
    RandomSource& random_;
    ArbiterState state_ = ArbiterState::Idle;
    TimePoint deadline_{};
    TimePoint deaf_until_{};  // BackingOff: what is heard before this does not count
    CollisionRound round_;
    std::optional<TimePoint> last_settled_;
    std::uint64_t collisions_ = 0;
};

}  // namespace ecpair::arbitration
