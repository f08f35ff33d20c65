// The cycle thread tells a stall as it happens: a cycle that runs past
// several deadlines (here the body sleeps five periods, as the machine not
// running the thread would look) is reported once, with the deadlines it
// skipped; cycles on time are not.

#include <atomic>
#include <chrono>
#include <thread>

#include <catch2/catch.hpp>

#include "ecpair/master/cycle_thread.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

TEST_CASE("the cycle thread reports a stall of several deadlines, once, with the deadlines skipped",
          "[master][cycle_thread]") {
    master::CycleThreadOptions options{2ms, 0, 0ns, "test-cycle"};
    options.stall_cycles = 4;
    std::atomic<int> cycles{0};
    master::CycleThread cycle(options, [&](link::Clock::time_point) {
        if (++cycles == 3) std::this_thread::sleep_for(5 * options.period);
    });
    std::atomic<int> stalls{0};
    std::atomic<std::uint64_t> skipped{0};
    cycle.set_stall_listener([&](std::chrono::nanoseconds, std::uint64_t missed) {
        ++stalls;
        skipped = missed;
    });
    cycle.start();
    for (int i = 0; i < 500 && cycles.load() < 10; ++i) std::this_thread::sleep_for(2ms);
    cycle.stop();
    REQUIRE(cycles.load() >= 10);
    // A loaded machine may add stalls of its own; the sleeping cycle is one of them.
    CHECK(stalls.load() >= 1);
    CHECK(skipped.load() >= 4);
    CHECK(cycle.timing().skipped >= 4);
}
