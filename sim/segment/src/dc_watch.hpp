#pragma once
// What the segment keeps of the distributed clocks between reports: which
// ESC is the reference clock, and the largest deviation from it seen since
// the last reset (DcReport::worst_deviation_ns).
//
// A slave's deviation (its system time minus the reference's at the same
// common time) is a straight line between the moments one of the two clocks
// changes (a step: new rate, jump, SYNC0 started or stopped), so its
// largest value lies at such a moment or now. After every call into an ESC
// the segment asks its DcCounters (one cheap call); a step of a slave that
// runs SYNC0 is measured just before and just after it, a step of the
// reference (or a new reference) is measured against every slave that runs
// SYNC0. A report measures them all once more, now.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ecpair/sim/esc.hpp"

namespace ecpair::sim::detail {

// a - b in the narrower width of the two DCs (32 bits when either has a 32-bit one).
std::int64_t system_time_difference(std::uint64_t a, std::uint64_t b, bool narrow);

class DcWatch {
public:
    // The slaves changed (built, power, plugged, removed): what was seen is
    // taken anew and the reference chosen again if it no longer holds.
    void rebuild(std::span<Esc> escs);

    // After a call into ESC `slave` whose frame reached it at `time_ns`.
    void after_call(std::span<Esc> escs, std::size_t slave, std::uint64_t time_ns) {
        const DcCounters counters = escs[slave].dc_counters();
        if (counters != seen_[slave]) changed(escs, slave, counters, time_ns);
    }

    std::optional<std::size_t> reference() const { return reference_; }
    bool reference_from_master() const { return from_master_; }
    // Notes a deviation measured for a report.
    void note(std::int64_t deviation_ns);
    std::int64_t worst() const { return worst_; }
    void reset_worst(std::int64_t current) { worst_ = current; }

private:
    void changed(std::span<Esc> escs, std::size_t slave, const DcCounters& counters, std::uint64_t time_ns);
    // Every slave that runs SYNC0 against the reference at `t` (the reference's own step, when there is one).
    void measure_all(std::span<Esc> escs, std::uint64_t t, const DcClockStep* reference_step);
    void choose_reference(std::span<Esc> escs);

    std::vector<DcCounters> seen_;
    std::optional<std::size_t> reference_;
    bool from_master_ = false;
    std::int64_t worst_ = 0;
};

}  // namespace ecpair::sim::detail
