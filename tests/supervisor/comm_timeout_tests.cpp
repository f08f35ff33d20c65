// The INACTIVE's watchdog on its partner, in virtual time.

#include <catch2/catch.hpp>

#include "ecpair/supervisor/comm_timeout.hpp"

using namespace ecpair::supervisor;
using namespace std::chrono_literals;

namespace {
const TimePoint t0{std::chrono::seconds(50)};
}

TEST_CASE("silence grows with our cycles and expires at the timeout", "[supervisor]") {
    CommTimeout timeout(20ms, 3ms, 1ms);
    timeout.reset(t0);
    for (int i = 1; i < 20; ++i) {
        timeout.cycle(t0 + std::chrono::milliseconds(i));
        REQUIRE_FALSE(timeout.expired());
    }
    timeout.cycle(t0 + 20ms);
    CHECK(timeout.expired());
    CHECK(timeout.silence() == 20ms);
    timeout.heard(t0 + 21ms);
    CHECK_FALSE(timeout.expired());
    CHECK(timeout.silence() == 0ms);
    CHECK(timeout.longest_silence() == 20ms);
}

TEST_CASE("one cycle counts at most two cycle times", "[supervisor]") {
    CommTimeout timeout(20ms, 3ms, 1ms);
    timeout.reset(t0);
    timeout.cycle(t0 + 500ms);  // this master stalled half a second
    CHECK(timeout.silence() == 2ms);
    CHECK_FALSE(timeout.expired());
}

TEST_CASE("a lost link shortens the wait to link_loss_confirm from then on", "[supervisor]") {
    CommTimeout timeout(20ms, 3ms, 1ms);
    timeout.reset(t0);
    for (int i = 1; i <= 5; ++i) timeout.cycle(t0 + std::chrono::milliseconds(i));
    timeout.link_lost(t0 + 6ms);
    CHECK(timeout.shortened());
    CHECK(timeout.limit() == 6ms + 3ms);
    timeout.cycle(t0 + 8ms);
    CHECK_FALSE(timeout.expired());
    timeout.cycle(t0 + 9ms);
    CHECK(timeout.expired());
    timeout.heard(t0 + 10ms);  // a CMF on the other link: the partner is there
    CHECK_FALSE(timeout.shortened());
    CHECK(timeout.limit() == 20ms);
}
