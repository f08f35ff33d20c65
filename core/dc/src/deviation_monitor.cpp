// The deviation window (see the header).

#include "ecpair/dc/deviation_monitor.hpp"

#include <algorithm>

namespace ecpair::dc {

SystemTimeDifference SystemTimeDifference::of(std::int64_t ns) {
    const auto magnitude = static_cast<std::uint64_t>(ns < 0 ? -ns : ns);
    const auto clipped = static_cast<std::uint32_t>(std::min<std::uint64_t>(magnitude, 0x7FFF'FFFFu));
    return SystemTimeDifference{clipped | (ns < 0 ? 0x8000'0000u : 0u)};
}

DeviationMonitor::DeviationMonitor(DeviationMonitorOptions options) : options_(options) {}

std::uint32_t DeviationMonitor::recent_worst_ns() const { return std::max(worst_this_span_, worst_previous_span_); }

std::optional<DeviationReport> DeviationMonitor::observe(std::uint64_t cycle, std::chrono::steady_clock::time_point now,
                                                         std::uint32_t deviation_ns) {
    last_ = deviation_ns;
    if (!span_started_ || now - span_start_ >= options_.recent_span) {
        worst_previous_span_ = span_started_ && now - span_start_ < 2 * options_.recent_span ? worst_this_span_ : 0;
        worst_this_span_ = 0;
        span_start_ = now;
        span_started_ = true;
    }
    worst_this_span_ = std::max(worst_this_span_, deviation_ns);

    const bool outside = deviation_ns > options_.window_ns;
    if (!out_) {
        if (!outside) return std::nullopt;
        out_ = true;
        left_cycle_ = cycle;
        cycles_out_total_ = 1;
        cycles_out_since_report_ = 0;
        worst_since_report_ = 0;
        worst_out_ = deviation_ns;
        inside_in_a_row_ = 0;
        last_report_ = now;
        return DeviationReport{DeviationReport::Kind::Left, deviation_ns, 1, cycle};
    }
    worst_since_report_ = std::max(worst_since_report_, deviation_ns);
    worst_out_ = std::max(worst_out_, deviation_ns);
    if (outside) {
        inside_in_a_row_ = 0;
        ++cycles_out_total_;
        ++cycles_out_since_report_;
    } else if (++inside_in_a_row_ >= options_.settle_cycles) {
        out_ = false;
        return DeviationReport{DeviationReport::Kind::Back, worst_out_, cycles_out_total_, left_cycle_};
    }
    if (now - last_report_ < options_.summary_interval || cycles_out_since_report_ == 0) return std::nullopt;
    DeviationReport summary{DeviationReport::Kind::Summary, worst_since_report_, cycles_out_since_report_, left_cycle_};
    last_report_ = now;
    cycles_out_since_report_ = 0;
    worst_since_report_ = 0;
    return summary;
}

}  // namespace ecpair::dc
