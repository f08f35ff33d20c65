// The rate limit is the deviation at D = +-(S - 0x7F); the phase slew is
// clamped so that the clock never runs outside it, and when the clamp
// shortens the slew's rate, the slew lasts longer instead (the quarter of Δt
// is always corrected in full, just more slowly).

#include "dc_time_loop.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::int32_t kStartMin = 0x0080;
constexpr std::int32_t kStartMax = 0x3FFF;
constexpr std::int32_t kDiffMargin = 0x7F;  // |D| <= S - 0x7F
constexpr std::int64_t kMaxDifference = std::int64_t{1} << 30;
constexpr std::int64_t kPhaseDivisor = 4;  // a quarter of Δt per received time
constexpr std::uint32_t kSignBit = 0x80000000U;
constexpr std::int64_t kMagnitudeMax = 0x7FFFFFFF;

using Wide = Int128;

}  // namespace

TimeLoop::TimeLoop(EscMemory& memory) : memory_(memory) {}

void TimeLoop::reset() {
    diff_ = 0;
    mean_q8_ = 0;
    last_t_.reset();
    publish();
}

std::int32_t TimeLoop::speed_counter_start() const {
    const auto written = static_cast<std::int32_t>(memory_.load<std::uint16_t>(reg::kDcSpeedCounterStart) & 0x7FFF);
    return std::clamp(written, kStartMin, kStartMax);
}

std::int64_t TimeLoop::deviation_q32(std::int32_t start, std::int32_t diff) {
    const std::int64_t denominator = 5 * std::int64_t{start + diff + 2} * std::int64_t{start - diff + 2};
    return static_cast<std::int64_t>((Wide{diff} << 32) / denominator);
}

ClockRate TimeLoop::steady_rate(ClockRate oscillator) const {
    const std::int64_t deviation = deviation_q32(speed_counter_start(), diff_);
    return oscillator - static_cast<ClockRate>((Wide{oscillator} * deviation) >> 32);
}

ClockAdjustment TimeLoop::on_received_time(std::uint64_t t, std::int32_t difference, ClockRate oscillator) {
    const std::int32_t start = speed_counter_start();
    const std::int32_t limit = start - kDiffMargin;
    const std::int64_t dt = std::clamp<std::int64_t>(difference, -kMaxDifference, kMaxDifference);

    // 0x092C: the mean of Δt.
    const int depth = memory_.u8(regs::kDcTimeDifferenceFilterDepth) & 0x0F;
    if (last_t_) {
        mean_q8_ += ((std::int64_t{difference} << 8) - mean_q8_) / (std::int64_t{1} << depth);
    } else {
        mean_q8_ = std::int64_t{difference} << 8;
    }

    // D: one step against the sign of Δt.
    if (dt > 0) diff_ = std::min(diff_ + 1, limit);
    if (dt < 0) diff_ = std::max(diff_ - 1, -limit);
    diff_ = std::clamp(diff_, -limit, limit);

    ClockAdjustment adjustment;
    adjustment.rate_after = steady_rate(oscillator);
    adjustment.rate = adjustment.rate_after;
    adjustment.until = t;
    const std::optional<std::uint64_t> previous = last_t_;
    last_t_ = t;
    publish();
    if (!previous || t <= *previous || dt == 0) return adjustment;

    // The phase slew: shift by -Δt/4 over the last interval, within the rate limit.
    const auto interval = static_cast<std::int64_t>(t - *previous);
    const std::int64_t shift = -dt / kPhaseDivisor;
    if (shift == 0) return adjustment;
    const std::int64_t max_deviation = deviation_q32(start, limit);
    const ClockRate fastest = oscillator + static_cast<ClockRate>((Wide{oscillator} * max_deviation) >> 32);
    const ClockRate slowest = oscillator - static_cast<ClockRate>((Wide{oscillator} * max_deviation) >> 32);
    const ClockRate wanted = adjustment.rate_after + static_cast<ClockRate>((Wide{shift} << 32) / interval);
    const ClockRate rate = std::clamp(wanted, slowest, fastest);
    const ClockRate extra = rate - adjustment.rate_after;
    if (extra == 0 || (extra > 0) != (shift > 0)) return adjustment;  // no room left in that direction
    const auto duration = static_cast<std::uint64_t>((Wide{shift} << 32) / extra);
    adjustment.rate = rate;
    adjustment.until = t + std::max<std::uint64_t>(duration, 1);
    return adjustment;
}

void TimeLoop::publish() {
    memory_.store<std::uint16_t>(regs::kDcSpeedCounterDiff, static_cast<std::uint16_t>(static_cast<std::int16_t>(diff_)));
    if (!last_t_) {
        memory_.store<std::uint32_t>(reg::kDcSystemTimeDifference, 0);  // the reset value: no received time yet
        return;
    }
    const std::int64_t mean = mean_q8_ >= 0 ? (mean_q8_ + 128) >> 8 : -((-mean_q8_ + 128) >> 8);
    const std::uint64_t magnitude = static_cast<std::uint64_t>(std::min(mean < 0 ? -mean : mean, kMagnitudeMax));
    const std::uint32_t sign = mean < 0 ? kSignBit : 0U;  // local copy smaller than the received time
    memory_.store<std::uint32_t>(reg::kDcSystemTimeDifference, static_cast<std::uint32_t>(magnitude) | sign);
}

}  // namespace ecpair::sim
