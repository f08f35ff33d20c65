// Every decision of the Arbiter, in virtual time: the clock is a time point
// the test moves, the randomness a script.

#include <catch2/catch.hpp>

#include "ecpair/arbitration/arbiter.hpp"
#include "scripted_random.hpp"

using namespace ecpair::arbitration;
using namespace std::chrono_literals;
using ecpair::test::ScriptedRandom;

namespace {

const TimePoint t0{std::chrono::seconds(1000)};

ArbiterOptions options() {
    ArbiterOptions o;
    o.listen_time = 200ms;
    o.backoff_min = 1ms;
    o.backoff_max = 10ms;
    o.repeat_window = 2s;
    o.settle_time = 3ms;
    return o;
}

// Steps every millisecond from `from` until a verdict other than Wait; returns it and when.
std::pair<Verdict, TimePoint> run(Arbiter& arbiter, TimePoint from, TimePoint heard_at = TimePoint::max()) {
    for (auto now = from; now < from + 10s; now += 1ms) {
        const auto verdict = arbiter.step(now, now == heard_at);
        if (verdict != Verdict::Wait) return {verdict, now};
    }
    return {Verdict::Wait, from + 10s};
}

}  // namespace

TEST_CASE("at start-up a master listens, plus a random jitter, before it takes the bus", "[arbitration]") {
    ScriptedRandom random({0.5});
    Arbiter arbiter(options(), random);
    arbiter.start(t0);
    CHECK(arbiter.state() == ArbiterState::Listening);
    CHECK(arbiter.deadline() == t0 + 200ms + 5ms);
    REQUIRE(random.asked.size() == 1);
    CHECK(random.asked[0].second == 10ms);  // the jitter is up to backoff_max

    const auto [verdict, at] = run(arbiter, t0);
    CHECK(verdict == Verdict::TakeBus);
    CHECK(at == t0 + 205ms);
    CHECK(arbiter.state() == ArbiterState::Idle);
}

TEST_CASE("an ACTIVE heard while listening makes the master yield at once", "[arbitration]") {
    ScriptedRandom random({0.0});
    Arbiter arbiter(options(), random);
    arbiter.start(t0);
    const auto [verdict, at] = run(arbiter, t0, t0 + 37ms);
    CHECK(verdict == Verdict::Yield);
    CHECK(at == t0 + 37ms);
    CHECK(arbiter.state() == ArbiterState::Idle);
}

TEST_CASE("a first collision backs off a random time within the range", "[arbitration]") {
    ScriptedRandom random({0.25});
    Arbiter arbiter(options(), random);
    const Contender ours{3, 5, 1};
    const Contender theirs{3, 5, 2};  // same reach: round 1 is random
    const auto& round = arbiter.collision(t0, ours, theirs);
    CHECK(round.number == 1);
    CHECK(round.kind == BackoffKind::Random);
    CHECK(round.backoff == 3ms + 1ms + 2250us);  // settle, then the draw
    REQUIRE(random.asked.size() == 1);
    CHECK(random.asked[0] == std::make_pair(std::chrono::nanoseconds(1ms), std::chrono::nanoseconds(10ms)));
    CHECK(arbiter.state() == ArbiterState::BackingOff);

    SECTION("silence until the backoff ends: take the bus") {
        const auto [verdict, at] = run(arbiter, t0);
        CHECK(verdict == Verdict::TakeBus);
        CHECK(at == t0 + 7ms);  // the first step at or after t0 + 6.25 ms
    }
    SECTION("the other master heard after the settle time: it took the bus back, yield") {
        const auto [verdict, at] = run(arbiter, t0, t0 + 5ms);
        CHECK(verdict == Verdict::Yield);
        CHECK(at == t0 + 5ms);
    }
    SECTION("what is heard within the settle time is the other's last frames: no yield") {
        const auto [verdict, at] = run(arbiter, t0, t0 + 2ms);
        CHECK(verdict == Verdict::TakeBus);
    }
}

TEST_CASE("a repeated collision is decided by the rule: the preferred waits least, the other defers",
          "[arbitration]") {
    ScriptedRandom random({0.9});
    Arbiter arbiter(options(), random);
    const Contender ours{3, 5, 0x0200000000A1};
    const Contender theirs{3, 5, 0x0200000000B2};
    arbiter.collision(t0, ours, theirs);
    const auto [first, settled] = run(arbiter, t0);
    REQUIRE(first == Verdict::TakeBus);

    // Again within the repeat window: round 2, the lower MAC (ours) is preferred.
    const auto& round = arbiter.collision(settled + 5ms, ours, theirs);
    CHECK(round.number == 2);
    CHECK(round.kind == BackoffKind::Preferred);
    CHECK(round.decided_by == DecidedBy::Mac);
    CHECK(round.backoff == 3ms + 1ms);

    // The other side of the same round defers twice the longest random backoff.
    ScriptedRandom other_random({0.9});
    Arbiter other(options(), other_random);
    other.collision(t0, theirs, ours);
    run(other, t0);
    const auto& deferring = other.collision(settled + 5ms, theirs, ours);
    CHECK(deferring.kind == BackoffKind::Deferring);
    CHECK(deferring.backoff == 3ms + 20ms);
}

TEST_CASE("a collision long after the last one starts again at round 1", "[arbitration]") {
    ScriptedRandom random({0.5});
    Arbiter arbiter(options(), random);
    const Contender ours{3, 5, 1};
    const Contender theirs{3, 5, 2};
    arbiter.collision(t0, ours, theirs);
    const auto [verdict, settled] = run(arbiter, t0);
    REQUIRE(verdict == Verdict::TakeBus);
    CHECK(arbiter.collision(settled + 3s, ours, theirs).number == 1);
    CHECK(arbiter.collisions() == 2);
}

TEST_CASE("after a double line break the master reaching more slaves is preferred in round 1", "[arbitration]") {
    ScriptedRandom random({0.5});
    Arbiter bigger(options(), random);
    const Contender big{7, 3, 0x0200000000FF};
    const Contender small{6, 2, 0x020000000001};
    const auto& round = bigger.collision(t0, big, small);
    CHECK(round.number == 1);
    CHECK(round.kind == BackoffKind::Preferred);
    CHECK(round.decided_by == DecidedBy::SlavesReached);
    CHECK(random.asked.empty());  // no draw: the rule decided

    Arbiter smaller(options(), random);
    CHECK(smaller.collision(t0, small, big).kind == BackoffKind::Deferring);
}

TEST_CASE("a collision with a master whose claims are unknown stays random", "[arbitration]") {
    ScriptedRandom random({0.1});
    Arbiter arbiter(options(), random);
    const Contender ours{3, 5, 1};
    arbiter.collision(t0, ours, std::nullopt);
    run(arbiter, t0);
    const auto& round = arbiter.collision(t0 + 20ms, ours, std::nullopt);
    CHECK(round.number == 2);
    CHECK(round.kind == BackoffKind::Random);
}

TEST_CASE("an idle arbiter decides nothing", "[arbitration]") {
    ScriptedRandom random({0.5});
    Arbiter arbiter(options(), random);
    CHECK(arbiter.state() == ArbiterState::Idle);
    CHECK(arbiter.step(t0, true) == Verdict::Wait);
}
