#pragma once
// The INACTIVE's record of the mailbox counter (ETG.1000.4: 1..7, the
// header's Cnt) the ACTIVE used last for each slave, read from the mailbox
// writes (FPWR of a slave's whole SM0) it forwards. A slave takes a message
// with the same counter as the last one for a repeat and does not act on
// it: a new ACTIVE that started counting from 1 again could see its first
// request to that slave ignored. It continues after these instead.
//
// Threads: observe() on the receive threads (either link), counters() from
// the cycle thread or any other; one atomic byte per slave.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "ecpair/eni/model.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::redundancy {

class MailboxCounterMirror {
public:
    explicit MailboxCounterMirror(const eni::EniConfig& eni);

    // A frame the ACTIVE sent, on its first pass through this master.
    void observe(const wire::ConstFrameView& frame);
    // Per slave in ENI order: the last counter seen, 0 when none.
    std::vector<std::uint8_t> counters() const;

private:
    struct Mailbox {
        std::size_t slave;
        std::uint32_t address;  // ADP = station, ADO = SM0 start
    };
    std::vector<Mailbox> mailboxes_;
    std::unique_ptr<std::atomic<std::uint8_t>[]> counters_;
    std::size_t slave_count_;
};

}  // namespace ecpair::redundancy
