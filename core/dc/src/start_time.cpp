// The SYNC0 start time (see the header).

#include "ecpair/dc/start_time.hpp"

#include <algorithm>

#include "ecpair/dc/dc_plan.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::dc {

std::optional<StartTimeParameters> start_time_parameters(const eni::EniConfig& eni, std::size_t slave,
                                                         const std::vector<bool>& present) {
    std::optional<std::size_t> reference;
    for (const auto candidate : reference_candidates(eni)) {
        if (candidate < present.size() && present[candidate]) {
            reference = candidate;
            break;
        }
    }
    if (!reference || slave >= eni.slaves.size()) return std::nullopt;
    StartTimeParameters parameters{bus::SlaveAddress::station(eni.slaves[*reference].info.phys_addr), 0, 0};
    if (const auto& dc = eni.slaves[slave].dc) {
        parameters.cycle_time_ns = dc->cycle_time0_ns.value_or(0);
        parameters.shift_time_ns = dc->shift_time_ns.value_or(0);
    }
    if (parameters.cycle_time_ns == 0 && !eni.cyclic.empty() && eni.cyclic.front().cycle_time_us) {
        parameters.cycle_time_ns = *eni.cyclic.front().cycle_time_us * 1000u;
    }
    return parameters;
}

std::uint64_t start_time(std::uint64_t system_time_ns, std::chrono::nanoseconds margin, std::uint32_t cycle_time_ns,
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

}  // namespace ecpair::dc
