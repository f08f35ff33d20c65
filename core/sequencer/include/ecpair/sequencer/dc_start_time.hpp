#pragma once
// The DC start time. ENIs write the SYNC0 start time (0x0990) as zeros:
// the master must put in a time shortly in the future of the slaves' system
// time. We read the reference clock's 64-bit system time (0x0910), add a
// margin (100 ms: enough for the remaining InitCmds of the transition), round
// up to a multiple of the slave's CycleTime0 and add its ShiftTime. Rounding
// to cycle multiples of the common system time keeps every slave's SYNC0 in
// phase even though each slave's start time is computed on its own.
//
// Reference clock: the present slave whose <DC> says ReferenceClock, else
// the first present slave with a <DC> element, else the first present slave.

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/eni/model.hpp"

namespace ecpair::sequencer {

inline constexpr std::chrono::milliseconds kDcStartMargin{100};

// `present[i]` tells whether EniConfig::slaves[i] is on the bus. nullopt when no slave is present.
std::optional<std::size_t> reference_clock_index(const eni::EniConfig& eni, const std::vector<bool>& present);

// ceil((system_time + margin) / cycle) * cycle + shift, never below 0.
// A cycle time of 0 means "no rounding".
std::uint64_t dc_start_time(std::uint64_t system_time_ns, std::chrono::nanoseconds margin, std::uint32_t cycle_time_ns,
                            std::int32_t shift_time_ns);

// Whether an InitCmd is the start-time write whose zeros must be replaced:
// an APWR/FPWR to 0x0990 whose data is all zeros.
bool is_zero_start_time_write(const eni::EcatCmd& cmd);

}  // namespace ecpair::sequencer
