#pragma once
// The mailbox of an emulated slave's stack, as SOES-like stacks run it: the
// MailboxHandler that checks each request's mailbox header, hands its body
// to the server of its protocol (a MailboxProtocol: CoE, FoE, EoE, SoE) and
// puts the replies into SM1 one at a time (docs/ESC_EMULATION.md "Mailbox").
//
//  - a request repeating the previous non-zero counter is a retransmission:
//    it is not executed again, the last reply is posted again;
//  - a header that is not acceptable gets a mailbox error reply (type 0):
//    length 0 or type 0 -> 0x0005 invalid header, a length past the mailbox
//    -> 0x0008 invalid size, a protocol the slave does not serve (or not in
//    its AL state: no CoE in BOOT) -> 0x0002 unsupported protocol;
//  - replies, and the messages the slave sends on its own (CoE emergencies),
//    wait in a short queue until SM1 is free: each carries the slave's
//    station address and a counter 1..7 of its own, none is longer than SM1;
//  - when the master has read SM1 and nothing waits, the protocol that
//    answered last may send more (the next fragment of an SDO Information
//    response).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sim/mailbox.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sim {

// What the mailbox needs of the slave it runs in.
class MailboxSlave {
public:
    // The source address of every reply (register 0x0010).
    virtual std::uint16_t station_address() const = 0;
    virtual eni::SlaveState al_state() const = 0;

protected:
    ~MailboxSlave() = default;
};

// How a protocol answers.
class MailboxReplies {
public:
    // Queues a reply of the protocol's type: `body` is what follows the
    // mailbox header, at most capacity() bytes (longer ones are not sent).
    virtual void reply(ConstBytes body) = 0;
    // A mailbox error reply (type 0) with `detail` (wire::mailbox_error_text).
    virtual void error(std::uint16_t detail) = 0;
    // The most a reply body may take: SM1's length less the mailbox header.
    virtual std::size_t capacity() const = 0;

protected:
    ~MailboxReplies() = default;
};

class MailboxProtocol {
public:
    virtual ~MailboxProtocol() = default;
    virtual wire::MailboxType type() const = 0;
    // Whether the stack offers the protocol in `state` (CoE not in BOOT; FoE there too).
    virtual bool serves_in(eni::SlaveState state) const = 0;
    // `body`: the request after the mailbox header (the header's Length bytes).
    virtual void on_request(ConstBytes body, MailboxReplies& replies) = 0;
    // SM1 was read and no reply waits: the next part of a longer answer, if any.
    virtual void on_reply_read(MailboxReplies& /*replies*/) {}
    // A new request (of any protocol) came: an answer still being sent in parts ends.
    virtual void end_answer() {}
    // The mailbox stopped (INIT, power): forget every transfer in progress.
    virtual void reset() {}
};

class MailboxServer final : public MailboxHandler {
public:
    static constexpr std::size_t kMaxQueued = 8;

    // `mailbox_in_size`: the length of SM1, the most a reply may take.
    MailboxServer(MailboxSlave& slave, std::size_t mailbox_in_size,
                  std::vector<std::unique_ptr<MailboxProtocol>> protocols);
    ~MailboxServer() override;
    MailboxServer(const MailboxServer&) = delete;
    MailboxServer& operator=(const MailboxServer&) = delete;

    void on_request(ConstBytes request, MailboxOutbox& outbox) override;
    void on_reply_read(MailboxOutbox& outbox) override;
    void on_stopped() override;

    // A message the slave sends on its own (body after the mailbox header),
    // queued like a reply. False when the queue is full or SM1 is too short.
    bool send_unsolicited(wire::MailboxType type, ConstBytes body, MailboxOutbox& outbox);
    // The server of `type`, nullptr when the slave has none.
    MailboxProtocol* protocol(wire::MailboxType type);

private:
    class Replies;
    void queue(wire::MailboxType type, ConstBytes body);
    void post_next(MailboxOutbox& outbox);

    MailboxSlave& slave_;
    std::size_t mailbox_in_size_;
    std::vector<std::unique_ptr<MailboxProtocol>> protocols_;
    std::deque<std::vector<std::uint8_t>> waiting_;  // whole messages not yet in SM1
    std::vector<std::uint8_t> last_reply_;           // the last one posted, for a retransmitted request
    MailboxProtocol* last_answered_ = nullptr;       // who may send more when SM1 is read
    std::uint8_t last_request_counter_ = 0;
    std::uint8_t reply_counter_ = 0;
};

}  // namespace ecpair::sim
