#pragma once
// The copies a cycle sends, gathered per link and sent together: one
// Link::send_batch per link (MAIN first) at the end of the cycle's sending,
// or earlier when a link's batch is full. Each copy has an owner number (the
// master's in-flight entry) that is told whether the copy left.
//
// When a link refuses a copy in a batch, the copies after it are tried one by
// one with send(), so that each gets its own outcome (a link that went down
// refuses them all; a single bad frame costs only itself).
//
// Preallocated: queueing and sending allocate nothing.

#include <array>
#include <cstddef>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/frame_batch.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/master/link_role.hpp"

namespace ecpair::master::detail {

class CycleBatches {
public:
    explicit CycleBatches(std::size_t copies_per_link);

    bool full(LinkRole role) const { return of(role).frames.full(); }
    // Copies the frame in (the caller may reuse its buffer). The batch must not be full.
    void add(LinkRole role, ConstBytes frame, std::size_t owner);

    // Sends what is queued on each link and empties the batches; calls
    // `outcome(role, owner, sent)` for every copy, in the order queued.
    template <class Outcome>
    void flush(link::Link& main, link::Link* red, Outcome&& outcome) {
        flush_one(LinkRole::Main, main, outcome);
        if (red != nullptr) flush_one(LinkRole::Red, *red, outcome);
    }

private:
    struct PerLink {
        explicit PerLink(std::size_t capacity) : frames(capacity) { owners.reserve(capacity); }
        link::FrameBatch frames;
        std::vector<std::size_t> owners;  // parallel to frames
    };

    PerLink& of(LinkRole role) { return links_[static_cast<std::size_t>(role)]; }
    const PerLink& of(LinkRole role) const { return links_[static_cast<std::size_t>(role)]; }

    template <class Outcome>
    void flush_one(LinkRole role, link::Link& link, Outcome& outcome) {
        PerLink& batch = of(role);
        const auto frames = batch.frames.frames();
        const std::size_t sent = link.send_batch(frames).sent;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const bool left = i < sent || (i > sent && link.send(frames[i]).has_value());
            outcome(role, batch.owners[i], left);
        }
        batch.frames.clear();
        batch.owners.clear();
    }

    std::array<PerLink, 2> links_;
};

}  // namespace ecpair::master::detail
