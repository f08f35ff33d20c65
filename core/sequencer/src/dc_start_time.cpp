// DC start time: choosing the reference clock and rounding the start time
// (see the header for the rules).

#include "ecpair/sequencer/dc_start_time.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {

std::optional<std::size_t> reference_clock_index(const eni::EniConfig& eni, const std::vector<bool>& present) {
    const auto is_present = [&present](std::size_t i) { return i < present.size() && present[i]; };
    std::optional<std::size_t> first_dc;
    std::optional<std::size_t> first_present;
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        if (!is_present(i)) continue;
        const auto& dc = eni.slaves[i].dc;
        if (dc && dc->reference_clock) return i;
        if (dc && !first_dc) first_dc = i;
        if (!first_present) first_present = i;
    }
    return first_dc ? first_dc : first_present;
}

std::uint64_t dc_start_time(std::uint64_t system_time_ns, std::chrono::nanoseconds margin, std::uint32_t cycle_time_ns,
                            std::int32_t shift_time_ns) {
    std::uint64_t start = system_time_ns + static_cast<std::uint64_t>(margin.count());
    if (cycle_time_ns != 0) start = (start + cycle_time_ns - 1) / cycle_time_ns * cycle_time_ns;
    if (shift_time_ns < 0) {
        const auto back = static_cast<std::uint64_t>(-static_cast<std::int64_t>(shift_time_ns));
        return start > back ? start - back : 0;
    }
    return start + static_cast<std::uint64_t>(shift_time_ns);
}

bool is_zero_start_time_write(const eni::EcatCmd& cmd) {
    const bool write = cmd.command == wire::Command::Apwr || cmd.command == wire::Command::Fpwr;
    return write && cmd.ado == wire::reg::kDcStartTime && !cmd.data.empty() &&
           std::all_of(cmd.data.begin(), cmd.data.end(), [](std::uint8_t b) { return b == 0; });
}

}  // namespace ecpair::sequencer
