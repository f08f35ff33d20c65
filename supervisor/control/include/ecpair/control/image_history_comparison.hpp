#pragma once
// Two pair members' image histories (ImageHistoryReply), compared cycle by
// cycle: the proof that the INACTIVE mirrored the ACTIVE's image. A cycle
// counts when one member recorded it as the ACTIVE (its own image) and the
// other as the mirror; a cycle both recorded as the ACTIVE means both sent
// in it (a takeover while the partner still ran) and is counted apart,
// never compared as a mirror. Only SAFEOP and OP cycles count: before them
// no cyclic frame carries outputs, so nothing can be mirrored.
//
// Used by `ecpairctl compare`, the pair tests and the fault campaign.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/control.pb.h"

namespace ecpair::control {

struct CycleDifference {
    std::uint64_t cycle = 0;
    bool inputs_differ = false;
    bool outputs_differ = false;
    bool state_differs = false;
};

struct ImageHistoryComparison {
    std::size_t common_cycles = 0;        // recorded by the ACTIVE on one side, the mirror on the other
    std::vector<CycleDifference> differ;  // of those, the ones that differ, oldest first
    std::vector<std::uint64_t> both_active;  // cycles both members recorded as the ACTIVE

    bool mirrored() const { return common_cycles > 0 && differ.empty() && both_active.empty(); }
    // "2400 cycles compared, 1 differ (cycle 4526: inputs); ..." for a log or a test message.
    std::string describe(std::size_t at_most = 5) const;
};

// newest: compare only the newest `newest` common cycles (0: all).
ImageHistoryComparison compare_image_histories(const ImageHistoryReply& a, const ImageHistoryReply& b,
                                               std::size_t newest = 0);

}  // namespace ecpair::control
