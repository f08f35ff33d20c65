#pragma once
// The SYNC0 start time. ENIs write the start time (0x0990) as zeros: the
// master puts in a time shortly after the slaves' common system time. The
// reference clock's 64-bit system time (0x0910) is read, a margin added
// (100 ms: enough for the rest of the slave's InitCmds of the transition),
// rounded up to a multiple of the slave's SYNC0 cycle time and its shift
// added. Rounding to cycle multiples of the common system time keeps every
// slave's SYNC0 in phase although each slave's start time is computed on
// its own -- the same for the slaves brought up at start-up and the ones
// Hot-Connect brings up later (one home for both: start_time_parameters).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::dc {

inline constexpr std::chrono::milliseconds kStartMargin{100};

// How the zero start time of one slave is replaced.
struct StartTimeParameters {
    bus::SlaveAddress reference_clock;  // whose system time (0x0910) is read
    std::uint32_t cycle_time_ns = 0;    // the slave's SYNC0 cycle time (0: no rounding)
    std::int32_t shift_time_ns = 0;     // the slave's ShiftTime
};

// The reference clock among the present slaves (the first present one of
// reference_candidates, dc_plan.hpp), by its station address; the cycle is the slave's
// CycleTime0, else the ENI's cycle time. nullopt when no slave is present.
std::optional<StartTimeParameters> start_time_parameters(const eni::EniConfig& eni, std::size_t slave,
                                                         const std::vector<bool>& present);

// ceil((system_time + margin) / cycle) * cycle + shift, never below 0.
// A cycle time of 0 means "no rounding".
std::uint64_t start_time(std::uint64_t system_time_ns, std::chrono::nanoseconds margin, std::uint32_t cycle_time_ns,
                         std::int32_t shift_time_ns);

// Whether an InitCmd is the start-time write whose zeros must be replaced:
// an APWR/FPWR to 0x0990 whose data is all zeros.
bool is_zero_start_time_write(const eni::EcatCmd& cmd);

}  // namespace ecpair::dc
