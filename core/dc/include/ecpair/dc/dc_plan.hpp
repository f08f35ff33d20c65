#pragma once
// What the ENI asks of Distributed Clocks, read once and checked before
// anything goes on the wire:
//   - which slaves run in DC mode: a <DC> element with a SYNC0 cycle time
//     (CycleTime0), or InitCmds that switch on the cyclic unit (a write of
//     0x0981, or of 0x0980 with a non-zero second byte) -- their SYNC0 cycle
//     time is then the one their InitCmds write to 0x09A0;
//   - their SYNC0/SYNC1 cycle times and shift;
//   - the reference clock: the slave whose <DC> says ReferenceClock, else
//     the first slave with a <DC> element (ring order), else the first slave;
//     among the slaves present (Hot-Connect) the first present one by that
//     rule (reference_candidates).
// Refused, with the slave and its ENI line:
//   - a SYNC0 cycle time that the bus cycle time is not a whole multiple of
//     (SYNC0 would slide against the frames);
//   - a slave in DC mode ahead of the reference clock in ring order: the
//     drift compensation's ARMW gives the reference's time only to the
//     slaves after it (the ones before get the master's bytes).
// Whether a slave's ESC has a DC unit at all is known only on the bus
// (register 0x0008): DcStartup checks that, and names the slave.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::dc {

struct DcSlave {
    std::size_t index = 0;  // EniConfig::slaves
    std::uint32_t sync0_cycle_ns = 0;
    std::uint32_t sync1_cycle_ns = 0;
    std::int32_t shift_ns = 0;
    int source_line = 0;  // the <Slave> element, or the InitCmd that switches DC on
};

// Reference clock candidates in the order they are tried: the slave whose
// <DC> says ReferenceClock, then every slave with a <DC> element in ring
// order; with no <DC> element anywhere, every slave in ring order.
std::vector<std::size_t> reference_candidates(const eni::EniConfig& eni);

class DcPlan {
public:
    // `cycle_time`: the bus cycle the master runs (the ENI's or the configured one).
    static Expected<DcPlan, std::string> build(const eni::EniConfig& eni, std::chrono::nanoseconds cycle_time);

    // Some slave runs in DC mode.
    bool used() const { return !slaves_.empty(); }
    const std::vector<DcSlave>& slaves() const { return slaves_; }
    const DcSlave* slave(std::size_t index) const;
    std::chrono::nanoseconds cycle_time() const { return cycle_time_; }
    // reference_candidates() of the ENI.
    const std::vector<std::size_t>& reference_candidates() const { return candidates_; }
    // The first present candidate; nullopt when none is present.
    std::optional<std::size_t> reference(const std::vector<bool>& present) const;

private:
    std::vector<DcSlave> slaves_;
    std::vector<std::size_t> candidates_;
    std::chrono::nanoseconds cycle_time_{0};
};

}  // namespace ecpair::dc
