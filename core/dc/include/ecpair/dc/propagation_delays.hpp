#pragma once
// The propagation delays of Distributed Clocks, from the receive-time
// latches of one frame (dc-and-diagnosis-facts.md, "The usual start-up").
//
// A frame that wrote 0x0900 leaves in every DC slave, in that slave's own
// local time, the time it arrived at each port (0x0900 + 4p) and at the
// processing unit (0x0918). The clocks are unrelated, so only differences
// within one slave mean anything. The segment is a tree rooted where the
// frame entered it. A slave is entered at one port (its entry port: 0 for
// frames from the master, 1 for a line entered from its far end) and sends
// the frame out of its other open ports one after the other, in processing
// order (0 -> 3 -> 1 -> 2 -> 0, cyclic, starting after the entry port); the
// frame comes back through each port before it leaves by the next, and
// finally leaves by the entry port. So, in the slave's own time:
//   - the frame left by port p when it came back through the open port
//     before p (or arrived at the entry port, for the first one);
//   - the time behind port p is its latch minus that departure: twice the
//     cable to the child plus the time the frame spent in the child's tree;
//   - the time the frame spends in a slave's tree is its last latch minus
//     its entry latch.
// Hence each cable's one-way delay (half of the parent's time behind the
// port, less the child's time in its tree), and, walking from the root, when
// the frame reached every slave's processing unit on one common time axis.
// A slave's delay is that time less the reference clock's: how long after
// the reference a frame reaches it (0x0928, written so that it compares the
// distributed time correctly).
//
// The internal forwarding time of an ESC is taken as zero: a difference
// between ports of one slave shows up as half of it in the cables' delays.
// A slave without DC unit has no latches: it counts as part of the cable
// from the DC slave before it to the one after it, which is right for a
// slave with one port leading on; DC slaves behind a slave without DC unit
// that branches cannot be measured (their delay is nullopt, with a reason).
//
// The pure arithmetic; DcStartup reads the latches and writes the results.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"

namespace ecpair::dc {

inline constexpr int kPorts = 4;

// One slave as the frame found it.
struct LatchedSlave {
    std::optional<std::size_t> parent;              // index in the list; nullopt: the frame entered the segment here
    int parent_port = 1;                            // the parent's port this slave hangs on
    int entry_port = 0;                             // the port facing the parent (or where the frame entered)
    std::array<bool, kPorts> open{};                // ports the frame passes (link, loop open); the entry port included
    bool has_dc = true;                             // false: no DC unit, no latches (the times below mean nothing)
    std::array<std::uint32_t, kPorts> port_time{};  // 0x0900 + 4p, local time
    std::uint64_t processing_time = 0;              // 0x0918, local time
};

struct SlaveDelay {
    // When the frame reached this slave's processing unit, in ns after it
    // reached the reference clock's (negative: before it). nullopt without
    // DC unit, or when it cannot be measured (`why`).
    std::optional<std::int64_t> delay;
    // One-way delay of the way from the DC slave before it (its parent, or
    // the DC slave before the slaves without DC unit in between), ns.
    std::optional<std::int64_t> cable;
    std::string why;
};

// `reference` is an index into `slaves`, which must have a DC unit.
// Errors: a list that is not one tree (no root or several, a cycle, two
// slaves on one port, a parent's port that is not open) or a reference
// without DC unit.
Expected<std::vector<SlaveDelay>, std::string> propagation_delays(const std::vector<LatchedSlave>& slaves,
                                                                  std::size_t reference);

// The port after `port` in processing order (0 -> 3 -> 1 -> 2 -> 0).
int next_port(int port);

// The physical tree of a segment as a bus scan sees it (DL status,
// bus/dl_ports.hpp): per position the ports with link and an open loop,
// visited from the master side (port 0 of position 0), depth first, in
// processing order: the slave at the next position hangs on the first such
// port not yet followed. An open port with nobody behind it once the
// positions ran out leads out of the segment: the ring's way back to the
// master's RED side. A frame that leaves by it never comes back to the
// slave, so delays can be measured only while such ports are closed.
struct Attachment {
    std::size_t parent = 0;
    int port = 1;
};
struct PortRef {
    std::size_t position = 0;
    int port = 1;
};
struct SegmentTree {
    std::vector<std::optional<Attachment>> attachment;  // per position; nullopt for position 0
    std::vector<PortRef> exits;                         // open ports leading out of the segment
};
// An error names the position that hangs nowhere (its ports and the count disagree).
Expected<SegmentTree, std::string> tree_from_ports(const std::vector<std::array<bool, kPorts>>& open);

// The slaves oriented from where frames enter: `entry` is the position
// entered and `entry_port` its port (0 from the master; for a line entered
// from its far end, the last slave and its port 1). Every slave reachable
// from there gets its parent, the parent's port and its entry port on the
// way from the entry; its open ports are those with a cable to another
// slave (exits are not: while measuring they are closed) plus the entry
// port. Index = position; latches are left for the caller to fill in.
std::vector<LatchedSlave> orient(const SegmentTree& tree, std::size_t entry, int entry_port);

}  // namespace ecpair::dc
