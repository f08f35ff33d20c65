// The clock is evaluated segment by segment: up to the end of the slew at
// its rate, after it at the rate that follows. local_at() rounds to the
// nearest ns (a clock a hair slower than nominal still reads whole ns);
// common_time_of() is its exact inverse: the first common time at which
// local_at() shows the value, rounded towards the future.

#include "dc_clock.hpp"

namespace ecpair::sim {
namespace {

constexpr int kFractionBits = 32;

using Fixed = Int128;

std::int64_t signed_difference(std::uint64_t a, std::uint64_t b) { return static_cast<std::int64_t>(a - b); }

// ceil(n / d) for d > 0.
Fixed divide_up(Fixed n, Fixed d) {
    const Fixed q = n / d;
    return (n % d != 0 && n > 0) ? q + 1 : q;
}

}  // namespace

ClockRate rate_of_drift(std::int64_t ppb) {
    return kNominalRate + static_cast<ClockRate>((Fixed{kNominalRate} * ppb) / 1'000'000'000);
}

void LocalClock::start(std::uint64_t at_ns, std::uint64_t local_ns, ClockRate rate) {
    t0_ = at_ns;
    local0_ = Fixed{local_ns} << kFractionBits;
    rate_ = rate;
    until_ = at_ns;
    rate_after_ = rate;
}

LocalClock::Fixed LocalClock::fixed_at(std::uint64_t t) const {
    const std::int64_t slew = signed_difference(until_, t0_);
    const std::int64_t dt = signed_difference(t, t0_);
    if (slew <= 0 || dt <= slew) {
        // Before the end of the slew (or without one, where rate_ == rate_after_ after it).
        const ClockRate rate = slew <= 0 ? rate_after_ : rate_;
        return local0_ + Fixed{dt} * rate;
    }
    return local0_ + Fixed{slew} * rate_ + Fixed{dt - slew} * rate_after_;
}

constexpr Fixed kHalf = Fixed{1} << (kFractionBits - 1);

std::uint64_t LocalClock::local_at(std::uint64_t t) const {
    return static_cast<std::uint64_t>((fixed_at(t) + kHalf) >> kFractionBits);
}

std::uint64_t LocalClock::common_time_of(std::uint64_t local_ns) const {
    const Fixed target = (Fixed{local_ns} << kFractionBits) - kHalf;
    const std::int64_t slew = signed_difference(until_, t0_);
    if (slew > 0) {
        const Fixed at_slew_end = local0_ + Fixed{slew} * rate_;
        if (target <= at_slew_end) return t0_ + static_cast<std::uint64_t>(divide_up(target - local0_, rate_));
        return until_ + static_cast<std::uint64_t>(divide_up(target - at_slew_end, rate_after_));
    }
    return t0_ + static_cast<std::uint64_t>(divide_up(target - local0_, rate_after_));
}

void LocalClock::set_rate(std::uint64_t t, ClockRate rate, std::uint64_t until, ClockRate rate_after) {
    rebase(t);
    rate_ = rate;
    until_ = signed_difference(until, t) > 0 ? until : t;
    rate_after_ = signed_difference(until, t) > 0 ? rate_after : rate;
}

void LocalClock::rebase(std::uint64_t t) {
    const Fixed local = fixed_at(t);
    if (signed_difference(until_, t) <= 0) {
        rate_ = rate_after_;
        until_ = t;
    }
    local0_ = local;
    t0_ = t;
}

}  // namespace ecpair::sim
