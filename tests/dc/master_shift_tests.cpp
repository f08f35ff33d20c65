// Master shift in virtual time: a master whose clock drifts against the
// reference clock sends a frame every cycle after a jittery delay; the cycle
// thread's schedule follows MasterShift's phase reference through PhaseLock,
// as ecpaird wires it. The frame must settle at its place in the DC cycle
// and stay there.

#include <catch2/catch.hpp>

#include <random>

#include "ecpair/dc/master_shift.hpp"
#include "ecpair/master/phase_lock.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

struct Loop {
    std::chrono::nanoseconds cycle = 1ms;
    std::chrono::nanoseconds lead = 500us;
    double drift_ppm = 100.0;                  // the reference clock runs this much fast against the master's
    std::uint64_t reference_offset = 0;        // its system time when the master's clock reads 0
    std::chrono::nanoseconds jitter{20'000};   // from the deadline to the frame at the reference, uniformly 0..jitter
    std::chrono::nanoseconds transit{30'000};  // and this much on top
    int path_change_at = -1;                   // from this cycle on the way to the reference is longer...
    std::chrono::nanoseconds path_change{0};   // ...by this much

    std::uint64_t reference_time(dc::TimePoint master) const {
        const auto t = static_cast<double>(master.time_since_epoch().count());
        return reference_offset + static_cast<std::uint64_t>(t * (1.0 + drift_ppm * 1e-6));
    }

    // Runs `cycles` cycles from a deadline at `start`; returns the error of every frame.
    std::vector<std::int64_t> run(dc::TimePoint start, int cycles, unsigned seed = 1) {
        dc::MasterShift shift(cycle, lead);
        master::PhaseLock lock(cycle);
        std::mt19937 random(seed);
        std::uniform_int_distribution<std::int64_t> late(0, jitter.count());
        std::vector<std::int64_t> errors;
        std::optional<std::pair<dc::TimePoint, std::uint64_t>> in_flight;  // the frame sent last cycle
        auto deadline = start;
        const auto target = static_cast<std::uint64_t>((cycle - lead).count());
        for (int k = 0; k < cycles; ++k) {
            if (in_flight) shift.observe(in_flight->first, deadline, in_flight->second);
            const auto path = transit + (path_change_at >= 0 && k >= path_change_at ? path_change : 0ns);
            const auto at_reference = deadline + path + std::chrono::nanoseconds(late(random));
            const auto time = reference_time(at_reference);
            errors.push_back(dc::phase_error(time, static_cast<std::uint64_t>(cycle.count()), target));
            in_flight = std::make_pair(deadline, time);
            deadline = lock.correct(deadline + cycle, shift.phase_reference());
        }
        return errors;
    }
};

std::int64_t worst_after(const std::vector<std::int64_t>& errors, std::size_t from) {
    std::int64_t worst = 0;
    for (std::size_t i = from; i < errors.size(); ++i) worst = std::max(worst, std::abs(errors[i]));
    return worst;
}

}  // namespace

TEST_CASE("unwrapping the ARMW's 32 bits and placing a time in its DC cycle", "[dc]") {
    CHECK(dc::unwrap_system_time(0x0000'0010u, 0x5'FFFF'FFF0ull) == 0x6'0000'0010ull);
    CHECK(dc::unwrap_system_time(0xFFFF'FFF0u, 0x6'0000'0010ull) == 0x5'FFFF'FFF0ull);
    CHECK(dc::unwrap_system_time(1234u, 0x7'0000'0000ull + 1000) == 0x7'0000'0000ull + 1234);
    CHECK(dc::phase_error(10'500'000, 1'000'000, 500'000) == 0);
    CHECK(dc::phase_error(10'600'000, 1'000'000, 500'000) == 100'000);
    CHECK(dc::phase_error(10'400'000, 1'000'000, 500'000) == -100'000);
    CHECK(dc::phase_error(10'000'000, 1'000'000, 500'000) == 500'000);  // (-cycle/2, cycle/2]
    CHECK(dc::phase_error(10'999'000, 1'000'000, 0) == -1'000);
}

TEST_CASE("the frame settles a tenth of a cycle from its place within 100 cycles, from any phase", "[dc]") {
    Loop loop;
    for (const std::int64_t start_us : {0, 130, 420, 499, 510, 777, 999}) {
        for (const double ppm : {0.0, 25.0, -100.0, 100.0}) {
            INFO("start " << start_us << " us, drift " << ppm << " ppm");
            loop.drift_ppm = ppm;
            loop.reference_offset = 3'000'000'000'123ull;
            const auto errors = loop.run(dc::TimePoint(std::chrono::microseconds(start_us)), 600);
            CHECK(worst_after(errors, 100) <= 100'000);  // a tenth of the 1 ms cycle
            // Settled: the jitter (0..20 us) around the target, nothing of the drift.
            CHECK(worst_after(errors, 400) <= 25'000);
        }
    }
}

TEST_CASE("a longer way to the reference (a takeover from the far end) is taken back within 100 cycles", "[dc]") {
    // 150 us more from cycle 300 on: 128 slaves passed unprocessed first.
    Loop loop;
    loop.path_change_at = 300;
    loop.path_change = 150us;
    const auto errors = loop.run(dc::TimePoint(0ns), 1000);
    CHECK(worst_after(std::vector<std::int64_t>(errors.begin(), errors.begin() + 300), 200) <= 25'000);
    CHECK(errors[300] >= 140'000);               // the jump itself
    CHECK(worst_after(errors, 400) <= 100'000);  // a tenth of a cycle within 100 cycles
    CHECK(worst_after(errors, 700) <= 25'000);
}

TEST_CASE("the schedule a master shift asks for: the next frame's predicted error taken out", "[dc]") {
    dc::MasterShift shift(1ms, 250us);
    CHECK_FALSE(shift.phase_reference());
    const dc::TimePoint sent(10ms);
    // Target: 750 us into the DC cycle. The frame came 40 us late; the schedule moved 10 us earlier since.
    shift.observe(sent, sent + 1ms - 10us, 7'000'790'000ull);
    CHECK(*shift.last_error() == 40us);
    CHECK(*shift.predicted_error() == 30us);
    CHECK(*shift.phase_reference() == sent + 1ms - 10us - 30us);
    shift.reset();
    CHECK_FALSE(shift.phase_reference());
}
