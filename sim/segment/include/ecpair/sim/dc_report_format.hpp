#pragma once
// `ecsim ctl dc`: the distributed clocks' truth (Segment::dc_report) as one
// line for people, or as one JSON object for scripts and tests. Both are
// the response line's text after "ok ".
//
// JSON (these names are a contract, docs/ECSIM.md):
//   {"now_ns":N, "reference":K|null, "reference_from":"master"|"first_dc"|null,
//    "synchronised":N, "max_abs_deviation_ns":N, "worst_deviation_ns":N,
//    "sync0_spread_ns":N|null, "sync0_missed":N,
//    "slaves":[{"position":K, "name":"...", "dc":"none"|"32-bit"|"64-bit",
//               "powered":bool, "deviation_ns":N|null, "drift_ppb":N,
//               "system_time_ns":N|null, "sync0":bool, "sync0_cycle_ns":N,
//               "last_sync0_ns":N|null, "last_sync0_system_ns":N|null,
//               "sync0_missed":N, "sync0_doubled":N}, ...]}

#include <string>

#include "ecpair/sim/segment.hpp"

namespace ecpair::sim {

std::string format_dc_text(const DcReport& report, const Segment& segment);
std::string format_dc_json(const DcReport& report, const Segment& segment);

}  // namespace ecpair::sim
