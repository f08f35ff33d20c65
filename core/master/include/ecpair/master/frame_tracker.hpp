#pragma once
// Frames in flight. Every frame the master sends gets a frame id (source MAC
// byte 1, design.md §2); the same id goes out on MAIN and on RED. Returned
// frames are matched to their slot by that id and to their copy by the NIC
// bytes of the source MAC (bytes 3-5: which of our NICs sent it). A frame
// whose NIC bytes are neither of ours comes from a foreign master.
//
// 256 frame ids last only a few cycles when a cycle sends dozens of frames,
// and a copy may come back long after its frame was given up (an overloaded
// segment, a stalled machine). So a returned copy must also be the frame
// that is in the slot now: every use of a slot has a generation, written
// into the index byte of each of its datagrams, and the copy's datagram
// structure (commands, lengths, index bytes, the addresses no slave changes)
// must be the one that was sent. Anything else is stale, never someone
// else's answer.
//
// Owned by the cycle thread: no locking. Slot buffers are allocated once;
// a slot keeps the frame as sent beside its returned copies.

#include <array>
#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/master/redundant_merge.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace ecpair::master {

enum class FrameKind : std::uint8_t { Cyclic, Acyclic, MasterRed };

struct SentFrame {
    FrameKind kind = FrameKind::Cyclic;
    std::uint16_t index = 0;  // which cyclic frame / acyclic batch / CMF part
    std::uint64_t cycle = 0;
    bool open = false;
};

enum class AcceptOutcome : std::uint8_t {
    Stored,       // a copy of one of our open frames
    Foreign,      // NIC bytes are not ours: another master sends on this bus
    Stale,        // ours, but its slot was closed (late) or reused
    Duplicate,    // this copy was already stored
    Malformed,    // not a decodable EtherCAT frame
};

class FrameTracker {
public:
    FrameTracker(wire::NicBytes main_nic, wire::NicBytes red_nic);

    // Opens the next frame id for `frame`, about to be sent: stamps the slot's
    // generation into the index byte of every datagram and keeps the frame's
    // signature. `frame` must be a valid EtherCAT frame.
    std::uint8_t open(FrameKind kind, std::uint16_t index, std::uint64_t cycle, Bytes frame);
    void close(std::uint8_t id) { slots_[id].sent.open = false; }

    AcceptOutcome accept(LinkRole arrived_on, ConstBytes frame);

    const SentFrame& sent(std::uint8_t id) const { return slots_[id].sent; }
    // The frame as it was sent (before any slave processed it): what a merge
    // compares the copies with.
    ConstBytes sent_bytes(std::uint8_t id) const {
        return ConstBytes(slots_[id].sent_bytes.data(), slots_[id].sent_size);
    }
    ReturnedCopy copy(std::uint8_t id, LinkRole sent_on) const;

    // The source MAC for the copy of frame `id` sent on `role`.
    wire::MacAddress source_mac(std::uint8_t id, LinkRole role, std::uint8_t retry_index = 0) const;

private:
    struct Slot {
        SentFrame sent;
        std::uint8_t generation = 0;
        std::uint64_t signature = 0;  // of the frame as sent
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> sent_bytes{};
        std::size_t sent_size = 0;
        std::array<std::array<std::uint8_t, wire::kMaxFrameSizeVlan>, 2> copies{};
        std::array<std::size_t, 2> sizes{};
        std::array<LinkRole, 2> arrived_on{};
        std::array<bool, 2> present{};
    };

    wire::NicBytes main_nic_;
    wire::NicBytes red_nic_;
    std::vector<Slot> slots_;  // 256, indexed by frame id
    std::uint8_t next_id_ = 0;
};

}  // namespace ecpair::master
