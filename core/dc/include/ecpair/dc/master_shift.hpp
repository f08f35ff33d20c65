#pragma once
// The master follows the reference clock ("master shift", as the common
// masters call it): the cycle thread's deadlines are moved so that the
// cyclic frame reaches the reference clock at a fixed point of the DC
// cycle, `lead` before the DC cycle boundary (system time a multiple of the
// bus cycle; the slaves' SYNC0 start times are such multiples plus their
// shift). The frames then keep their place between the SYNC0 edges however
// the master's clock and the reference clock drift apart.
//
// Every cycle the drift compensation's ARMW reads the reference clock's
// system time as the frame passes it. observe() gets that time with the
// deadline of the cycle that sent the frame and the deadline of the cycle
// that reads it (one later); the error of the frame now being sent is
// predicted from the last error and the deadline moves made since (the
// frame measured left before the last move). phase_reference() gives the
// cycle thread (PhaseLock) a boundary of the schedule that puts the next
// frame on target; PhaseLock steps a quarter of the way each cycle (at most
// an eighth of a cycle), which smooths the master's jitter out of the
// schedule. The drift between the clocks shows as a lag of four times the
// drift per cycle (0.4 µs at 1 ms and 100 ppm).
//
// Pure arithmetic in the caller's time: tested in virtual time.

#include <chrono>
#include <cstdint>
#include <optional>

namespace ecpair::dc {

using TimePoint = std::chrono::steady_clock::time_point;

// The 64-bit system time whose low 32 bits were read, nearest `predicted`.
std::uint64_t unwrap_system_time(std::uint32_t low, std::uint64_t predicted);

// Where a system time lies in its DC cycle relative to `target` (a position
// in the cycle, [0, cycle)): in (-cycle/2, cycle/2], positive when later.
std::int64_t phase_error(std::uint64_t system_time, std::uint64_t cycle_ns, std::uint64_t target_ns);

class MasterShift {
public:
    // `lead`: the frame reaches the reference clock this long before the DC
    // cycle boundary (0 < lead < cycle).
    MasterShift(std::chrono::nanoseconds cycle, std::chrono::nanoseconds lead);

    // The reference clock's system time when the frame sent by the cycle of
    // deadline `sent` passed it, read in the cycle of deadline `now`.
    void observe(TimePoint sent, TimePoint now, std::uint64_t reference_time);
    // Forget what was observed (a takeover: another master's frames).
    void reset();

    // The error of the last frame observed: positive when it reached the
    // reference clock later than it should; nullopt before any.
    std::optional<std::chrono::nanoseconds> last_error() const;
    // The error predicted for the frame sent by the cycle of deadline `now`
    // of the last observe().
    std::optional<std::chrono::nanoseconds> predicted_error() const;
    // A boundary of the schedule that would put the next frame on target:
    // CycleThread's phase reference. nullopt before the first observation.
    std::optional<TimePoint> phase_reference() const;
    std::chrono::nanoseconds lead() const { return lead_; }
    std::chrono::nanoseconds cycle() const { return cycle_; }

private:
    std::chrono::nanoseconds cycle_;
    std::chrono::nanoseconds lead_;
    std::optional<std::chrono::nanoseconds> error_;
    std::optional<std::chrono::nanoseconds> predicted_;
    TimePoint now_{};
};

}  // namespace ecpair::dc
