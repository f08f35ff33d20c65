#pragma once
// Where the kernel store-and-forward finds its answers to the TAP bridge's
// polls. The kernel cannot pack frames from a user-space queue as a poll
// passes, so the channel prepares the next answer ahead of the polls: a few
// slots, each a sealed ANSWER datagram's data for a poll of exactly its
// size. The first poll of that size to pass takes the newest slot (its id is
// written into the slot) and the poll's other copy gets the same bytes; the
// channel sees which slot a poll took and prepares the next one
// (AcyclicMasterRedChannel::prepare_answers). KernelForwarding implements it
// over the program's memory; tests implement it in plain memory.

#include <cstddef>
#include <cstdint>

#include "ecpair/common/bytes.hpp"

namespace ecpair::redundancy {

class PreparedPollAnswers {
public:
    virtual ~PreparedPollAnswers() = default;

    virtual std::size_t slots() const = 0;
    // 0 while no poll took the slot's answer, else that poll's session << 32 | sequence.
    virtual std::uint64_t claimed_by(std::size_t slot) const = 0;
    // Makes `data` the answer of `slot`, not yet claimed, and the slot the next poll takes.
    virtual void publish(std::size_t slot, ConstBytes data) = 0;
    // No slot answers any poll until the next publish().
    virtual void withdraw_all() = 0;
};

}  // namespace ecpair::redundancy
