// The link guard's decisions in virtual time: no heartbeat before the first
// one is no hang; hang_timeout without one takes the links down once; a
// heartbeat whose cycle did not advance does not count; links stay down
// when heartbeats resume until ecpaird asks; end-of-file and shutdown take
// them down and finish; failures are reported with the errno.

#include <catch2/catch.hpp>

#include <vector>

#include "ecpair/linkguard/guard_logic.hpp"

using namespace ecpair::linkguard;
using namespace std::chrono_literals;
using Clock = GuardLogic::Clock;

namespace {

struct Fixture {
    Fixture() : logic(options(), io()) {}

    static GuardOptions options() {
        GuardOptions o;
        o.name = "m1";
        o.links = "MAIN m1-main, RED m1-red";
        o.hang_timeout = 50ms;
        return o;
    }
    GuardLogic::Io io() {
        return GuardLogic::Io{[this](bool up) {
                                  sets.push_back(up);
                                  LinkResult r;
                                  r.links = fail_red ? kMainLink : kMainLink | kRedLink;
                                  if (fail_red) {
                                      r.error = 1;  // EPERM
                                      r.message = "m1-red: setting it down: Operation not permitted";
                                  }
                                  return r;
                              },
                              [this](const GuardMessage& m) { reports.push_back(m); }};
    }

    void beat(std::uint64_t cycle, Clock::time_point at) {
        GuardMessage m;
        m.kind = GuardMessageKind::Heartbeat;
        m.cycle = cycle;
        logic.on_message(m, at);
    }
    void command(GuardMessageKind kind, Clock::time_point at) {
        GuardMessage m;
        m.kind = kind;
        logic.on_message(m, at);
    }

    Clock::time_point t0 = Clock::time_point() + 1000s;
    std::vector<bool> sets;
    std::vector<GuardMessage> reports;
    bool fail_red = false;
    GuardLogic logic;
};

}  // namespace

TEST_CASE_METHOD(Fixture, "link guard: before the first heartbeat nothing is a hang", "[linkguard]") {
    command(GuardMessageKind::LinksUp, t0);
    REQUIRE(sets == std::vector<bool>{true});
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].kind == GuardMessageKind::LinksAreUp);
    CHECK(reports[0].links == (kMainLink | kRedLink));
    CHECK(reports[0].error == 0);
    CHECK(logic.state() == GuardState::Idle);
    CHECK_FALSE(logic.deadline());
    logic.on_time(t0 + 1h);
    CHECK(sets.size() == 1);
}

TEST_CASE_METHOD(Fixture, "link guard: hang_timeout without a heartbeat takes the links down once", "[linkguard]") {
    beat(100, t0);
    REQUIRE(logic.state() == GuardState::Watching);
    REQUIRE(logic.deadline() == t0 + 50ms);
    beat(120, t0 + 20ms);  // pushes the deadline
    CHECK(logic.deadline() == t0 + 70ms);
    logic.on_time(t0 + 69ms);
    CHECK(sets.empty());
    logic.on_time(t0 + 70ms);
    REQUIRE(sets == std::vector<bool>{false});
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].kind == GuardMessageKind::LinksTakenDown);
    CHECK(reports[0].reason == DownReason::HeartbeatStopped);
    CHECK(reports[0].silence_ms == 50);
    CHECK(reports[0].cycle == 120);
    CHECK(reports[0].links == (kMainLink | kRedLink));
    CHECK(logic.state() == GuardState::LinksDown);
    CHECK_FALSE(logic.deadline());
    logic.on_time(t0 + 1h);
    CHECK(sets.size() == 1);  // once
}

TEST_CASE_METHOD(Fixture, "link guard: a heartbeat whose cycle did not advance does not count", "[linkguard]") {
    beat(100, t0);
    beat(100, t0 + 30ms);
    beat(99, t0 + 40ms);
    CHECK(logic.deadline() == t0 + 50ms);
    logic.on_time(t0 + 50ms);
    CHECK(sets == std::vector<bool>{false});
}

TEST_CASE_METHOD(Fixture, "link guard: links stay down when the cycle resumes, until ecpaird asks", "[linkguard]") {
    beat(100, t0);
    logic.on_time(t0 + 60ms);
    REQUIRE(logic.state() == GuardState::LinksDown);
    reports.clear();

    beat(101, t0 + 3s);  // SIGCONT: the cycle advances again
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].kind == GuardMessageKind::HeartbeatResumed);
    CHECK(reports[0].silence_ms == 3000);
    CHECK(reports[0].cycle == 101);
    beat(102, t0 + 3010ms);
    CHECK(reports.size() == 1);  // reported once
    CHECK(sets == std::vector<bool>{false});  // nothing brought up
    CHECK(logic.state() == GuardState::LinksDown);
    CHECK_FALSE(logic.deadline());

    command(GuardMessageKind::LinksUp, t0 + 3020ms);
    CHECK(sets == std::vector<bool>{false, true});
    REQUIRE(reports.size() == 2);
    CHECK(reports[1].kind == GuardMessageKind::LinksAreUp);
    CHECK(reports[1].silence_ms == 2960);  // down from t0 + 60 ms to t0 + 3020 ms
    CHECK(logic.state() == GuardState::Watching);
    CHECK(logic.deadline() == t0 + 3060ms);
}

TEST_CASE_METHOD(Fixture, "link guard: links up while the cycle still stands still go down again at once",
                 "[linkguard]") {
    beat(100, t0);
    logic.on_time(t0 + 50ms);
    command(GuardMessageKind::LinksUp, t0 + 200ms);
    CHECK(sets == std::vector<bool>{false, true, false});
    CHECK(logic.state() == GuardState::LinksDown);
}

TEST_CASE_METHOD(Fixture, "link guard: ecpaird gone takes the links down and finishes, without a report",
                 "[linkguard]") {
    beat(100, t0);
    logic.on_daemon_gone(t0 + 3ms);
    CHECK(sets == std::vector<bool>{false});
    CHECK(reports.empty());  // nobody to tell
    CHECK(logic.finished());
    beat(101, t0 + 4ms);
    logic.on_time(t0 + 1h);
    CHECK(sets.size() == 1);
}

TEST_CASE_METHOD(Fixture, "link guard: ecpaird gone during start-up or after a hang still takes the links down",
                 "[linkguard]") {
    SECTION("before any heartbeat") { logic.on_daemon_gone(t0); }
    SECTION("after a hang") {
        beat(100, t0);
        logic.on_time(t0 + 50ms);
        logic.on_daemon_gone(t0 + 100ms);
        CHECK(sets.size() == 2);
    }
    CHECK(sets.back() == false);
    CHECK(logic.finished());
}

TEST_CASE_METHOD(Fixture, "link guard: shutdown takes the links down, reports it, and finishes", "[linkguard]") {
    beat(100, t0);
    command(GuardMessageKind::Shutdown, t0 + 10ms);
    CHECK(sets == std::vector<bool>{false});
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].kind == GuardMessageKind::LinksTakenDown);
    CHECK(reports[0].reason == DownReason::DaemonStopping);
    CHECK(reports[0].silence_ms == 10);
    CHECK(logic.finished());
    command(GuardMessageKind::LinksUp, t0 + 20ms);  // too late: finished
    CHECK(sets.size() == 1);
}

TEST_CASE_METHOD(Fixture, "link guard: a link that cannot be set is reported with its errno", "[linkguard]") {
    fail_red = true;
    beat(100, t0);
    logic.on_time(t0 + 50ms);
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].links == kMainLink);
    CHECK(reports[0].error == 1);
    CHECK(logic.state() == GuardState::LinksDown);
}

TEST_CASE_METHOD(Fixture, "link guard: messages only the guard sends are ignored", "[linkguard]") {
    command(GuardMessageKind::LinksTakenDown, t0);
    command(GuardMessageKind::LinksAreUp, t0);
    command(GuardMessageKind::HeartbeatResumed, t0);
    CHECK(sets.empty());
    CHECK(reports.empty());
    CHECK(logic.state() == GuardState::Idle);
}
