// Master shift (see the header).

#include "ecpair/dc/master_shift.hpp"

namespace ecpair::dc {

std::uint64_t unwrap_system_time(std::uint32_t low, std::uint64_t predicted) {
    const auto difference = static_cast<std::int32_t>(low - static_cast<std::uint32_t>(predicted));
    return predicted + static_cast<std::uint64_t>(static_cast<std::int64_t>(difference));
}

std::int64_t phase_error(std::uint64_t system_time, std::uint64_t cycle_ns, std::uint64_t target_ns) {
    if (cycle_ns == 0) return 0;
    const auto cycle = static_cast<std::int64_t>(cycle_ns);
    auto error = static_cast<std::int64_t>(system_time % cycle_ns) - static_cast<std::int64_t>(target_ns % cycle_ns);
    if (error > cycle / 2) error -= cycle;
    if (error <= -cycle / 2) error += cycle;
    return error;
}

MasterShift::MasterShift(std::chrono::nanoseconds cycle, std::chrono::nanoseconds lead) : cycle_(cycle), lead_(lead) {}

void MasterShift::observe(TimePoint sent, TimePoint now, std::uint64_t reference_time) {
    const auto cycle = static_cast<std::uint64_t>(cycle_.count());
    if (cycle == 0) return;
    const auto target = (cycle - static_cast<std::uint64_t>(lead_.count()) % cycle) % cycle;
    const std::chrono::nanoseconds error{phase_error(reference_time, cycle, target)};
    error_ = error;
    // The frame of `now` left (now - sent - cycle) later in the schedule than
    // the one measured: it will be that much later at the reference.
    predicted_ = error + std::chrono::duration_cast<std::chrono::nanoseconds>(now - sent) - cycle_;
    now_ = now;
}

void MasterShift::reset() {
    error_.reset();
    predicted_.reset();
}

std::optional<std::chrono::nanoseconds> MasterShift::last_error() const { return error_; }

std::optional<std::chrono::nanoseconds> MasterShift::predicted_error() const { return predicted_; }

std::optional<TimePoint> MasterShift::phase_reference() const {
    if (!predicted_) return std::nullopt;
    return now_ - std::chrono::duration_cast<TimePoint::duration>(*predicted_);
}

}  // namespace ecpair::dc
