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
// With one processed copy, that copy is the answer. With two (a broken
// ring), every slave processed exactly one of them, and how the halves of a
// datagram make one answer depends on its command (merge_rule_of): a write
// comes back as it was sent, a single addressed slave answers in one copy
// only (the other still carries what was sent: for APRW/FPRW the written
// bytes, which must not end up in the read value), broadcast reads OR, a
// logical datagram's bits are each changed by at most one slave. Working
// counters add up, and the IRQ fields are ORed: each copy carries the event
// requests of the slaves on its side of the break.

#include <cstdint>
#include <optional>
#include <string>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/wire/command.hpp"

namespace ecpair::master {

enum class CopyPath : std::uint8_t { Missing, ThroughRing, Unprocessed, BouncedMain, BouncedRed };
std::string_view to_string(CopyPath path);

// sent_on: the NIC that sent the copy (its redundancy bit); arrived_on: where it came back.
CopyPath classify(LinkRole sent_on, LinkRole arrived_on);

struct ReturnedCopy {
    ConstBytes frame;  // empty when the copy did not come back
    CopyPath path = CopyPath::Missing;
};

// How the data of a datagram's two processed halves becomes one answer.
enum class MergeRule : std::uint8_t {
    AsSent,       // no slave changes the data: either copy (the first)
    CountedCopy,  // one addressed slave answers: the copy whose WKC counted it
    ChangedCopy,  // one slave answers, the others take the data and count too: the copy that differs from the sent
    Or,           // every slave ORs into the data: the OR of both
    ChangedBits,  // each bit is changed by at most one slave: per bit, the copy that changed it
};
MergeRule merge_rule_of(wire::Command command);
std::string_view to_string(MergeRule rule);

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
// `sent` is the frame as it was sent (its datagrams' data before any slave
// saw them). With a single copy the result is that copy. With none there is
// nothing to merge (error).
Expected<MergeResult, MergeError> merge_copies(ConstBytes sent, const ReturnedCopy& main_copy,
                                               const ReturnedCopy& red_copy, Bytes out);

}  // namespace ecpair::master
