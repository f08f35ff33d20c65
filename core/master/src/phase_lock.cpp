#include "ecpair/master/phase_lock.hpp"

#include <algorithm>

namespace ecpair::master {

std::chrono::nanoseconds PhaseLock::error(link::Clock::time_point next, link::Clock::time_point reference) const {
    const auto period = period_.count();
    auto e = std::chrono::duration_cast<std::chrono::nanoseconds>(reference - next).count() % period;  // (-period, period)
    if (e > period / 2) e -= period;
    if (e <= -period / 2) e += period;
    return std::chrono::nanoseconds(e);
}

link::Clock::time_point PhaseLock::correct(link::Clock::time_point next,
                                           std::optional<link::Clock::time_point> reference) const {
    if (!reference || period_.count() <= 0) return next;
    const auto e = error(next, *reference);
    const auto fast = period_ / 8;
    const auto step = std::abs(e.count()) < fast.count() ? e / 4 : std::clamp(e, -fast, fast);
    return next + std::chrono::duration_cast<link::Clock::duration>(step);
}

}  // namespace ecpair::master
