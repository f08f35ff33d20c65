#pragma once
// Cable redundancy, receive side (design.md §3): every frame goes out on
// MAIN and on RED with the same frame id; the copies come back and are
// merged into one frame as if it had passed an intact ring.
//
// Where a copy comes back tells what happened to it:
//
//   copy sent on  back on   path            meaning
//   MAIN          RED       ThroughRing     every slave processed it: ring closed
//   RED           MAIN      Unprocessed     passed the slaves in reverse, untouched
//   MAIN          MAIN      BouncedMain     processed by the slaves up to a break
//   RED           RED       BouncedRed      processed by the slaves beyond a break
//
// The merged data is the OR of the processed copies' data (a slave that did
// not process a copy left its bytes as sent: zeros for reads, the same
// outputs for writes), and the WKC is the sum over both copies.

#include <cstdint>
#include <optional>
#include <string>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/master/link_role.hpp"

namespace ecpair::master {

enum class CopyPath : std::uint8_t { Missing, ThroughRing, Unprocessed, BouncedMain, BouncedRed };
std::string_view to_string(CopyPath path);

// sent_on: the NIC that sent the copy (its redundancy bit); arrived_on: where it came back.
CopyPath classify(LinkRole sent_on, LinkRole arrived_on);

struct ReturnedCopy {
    ConstBytes frame;  // empty when the copy did not come back
    CopyPath path = CopyPath::Missing;
};

struct MergeResult {
    bool complete = false;     // the merged frame equals one pass through an intact ring
    bool ring_closed = false;  // a MAIN copy came round the whole ring
    bool ring_broken = false;  // a copy came back on the NIC that sent it (a missing copy proves nothing)
    std::size_t size = 0;      // bytes of the merged frame in the output buffer
};

struct MergeError {
    std::string message;  // why the copies cannot be merged (different datagram layout, bad frame)
};

// Writes the merged frame into `out` (at least as large as the larger copy).
// With a single copy the result is that copy. With none there is nothing to merge (error).
Expected<MergeResult, MergeError> merge_copies(const ReturnedCopy& main_copy, const ReturnedCopy& red_copy, Bytes out);

}  // namespace ecpair::master
