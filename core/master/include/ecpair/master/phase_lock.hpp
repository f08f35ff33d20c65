#pragma once
// Moves a free-running cycle onto another schedule: a standby master locks
// its cycle to the arrival of its ACTIVE partner's frames (acontis: both
// masters run on frame arrival, so they do not drift), so that at a hand-off
// the new ACTIVE sends in the slot where the old one would have.
//
// The reference is any boundary of the schedule to follow. The deadline the
// thread would use next is moved towards the nearest such boundary: a small
// error is taken a quarter at a time (the reference jitters with the
// partner's wake-up and the frame's way here), a large one at most an eighth
// of a period per cycle, so that a wild reference can neither stall the
// cycle nor make it burst. Pure arithmetic: the cycle thread applies it.

#include <chrono>
#include <optional>

#include "ecpair/link/link.hpp"

namespace ecpair::master {

class PhaseLock {
public:
    explicit PhaseLock(std::chrono::nanoseconds period) : period_(period) {}

    // The deadline to use instead of `next`; `next` itself without a reference.
    link::Clock::time_point correct(link::Clock::time_point next,
                                    std::optional<link::Clock::time_point> reference) const;

    // How far `next` is from the reference schedule, in (-period/2, period/2]:
    // positive when the reference's boundary comes later.
    std::chrono::nanoseconds error(link::Clock::time_point next, link::Clock::time_point reference) const;

private:
    std::chrono::nanoseconds period_;
};

}  // namespace ecpair::master
