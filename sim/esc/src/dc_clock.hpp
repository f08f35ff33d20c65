#pragma once
// An ESC's local clock (datasheet I §9.1) against the common time base, the
// simulation time in ns that the segment gives every frame and every call.
//
// The clock is a straight line between the moments its rate changes: from
// an anchor (common time t0, local time L0) it runs at `rate` local ns per
// common ns until `slew_until`, then at `rate_after`. The ESC's oscillator
// sets the base rate (its drift in ppb); the drift compensation loop changes
// the rate at the frames that write 0x0910 (dc_time_loop.hpp), and a slew of
// the loop's phase correction ends by itself. Nothing ticks: the local time
// at any common time is computed, and so is the common time at which the
// local time reaches a value (SYNC0 edges, dc_sync_unit.hpp).
//
// Times are kept in fixed point, 2^-32 ns, so that a rate is exact to
// 2^-32 (0.0002 ppb) and rebasing at every rate change loses nothing.
// Common times before the anchor are extrapolated backwards (frames carried
// one after the other may reach a slave slightly out of time order).

#include <cstdint>

namespace ecpair::sim {

// 128-bit intermediate products (GCC and Clang; __extension__ keeps -Wpedantic quiet).
__extension__ typedef __int128 Int128;

// The rate of a clock: local ns per common ns, in units of 2^-32.
using ClockRate = std::int64_t;
inline constexpr ClockRate kNominalRate = ClockRate{1} << 32;

// The rate of an oscillator `ppb` parts per billion fast (negative: slow).
ClockRate rate_of_drift(std::int64_t ppb);

class LocalClock {
public:
    // The clock shows `local_ns` at common time `at_ns` and runs at `rate` from then on.
    void start(std::uint64_t at_ns, std::uint64_t local_ns, ClockRate rate);

    // The local time at common time `t` (ns, rounded to the nearest).
    std::uint64_t local_at(std::uint64_t t) const;
    // The first common time at which the local time is `local_ns` or later.
    std::uint64_t common_time_of(std::uint64_t local_ns) const;

    // From common time `t` on the clock runs at `rate` until `until`, then
    // at `rate_after` (no slew: until == t).
    void set_rate(std::uint64_t t, ClockRate rate, std::uint64_t until, ClockRate rate_after);

private:
    using Fixed = Int128;  // local time in 2^-32 ns

    Fixed fixed_at(std::uint64_t t) const;
    // Moves the anchor to `t` without changing the line (so that the
    // fixed-point products stay small).
    void rebase(std::uint64_t t);

    std::uint64_t t0_ = 0;
    Fixed local0_ = 0;
    ClockRate rate_ = kNominalRate;
    std::uint64_t until_ = 0;  // the slew ends here (until_ <= t0_: no slew)
    ClockRate rate_after_ = kNominalRate;
};

}  // namespace ecpair::sim
