#pragma once
// The PDI-side seam of an emulated ESC's mailbox (SM0 = master to slave,
// SM1 = slave to master, as every SOES-like stack uses them).
//
// When the master has completely written the receive mailbox, the ESC hands
// the whole SM0 buffer to the installed MailboxHandler at the end of that
// frame and frees SM0 again. The handler answers through the MailboxOutbox,
// which copies a reply into SM1 and marks it full; when the master has read
// SM1 completely the handler hears about it, so it can post the next reply.
// A protocol server (CoE, later) is one MailboxHandler. The messages
// themselves are coded with wire/mailbox.hpp.

#include "ecpair/common/bytes.hpp"

namespace ecpair::sim {

// Where a handler puts its replies: the slave-to-master mailbox (SM1).
class MailboxOutbox {
public:
    // Copies `reply` into SM1 (cut to the SM1 length) and marks it full.
    // False when SM1 still holds an unread reply or the mailbox is not running.
    virtual bool post(ConstBytes reply) = 0;
    // True while SM1 holds a reply the master has not read yet.
    virtual bool full() const = 0;

protected:
    ~MailboxOutbox() = default;
};

class MailboxHandler {
public:
    virtual ~MailboxHandler() = default;
    // The master wrote the receive mailbox completely; `request` is the whole
    // SM0 buffer (header first). Called at the end of that frame.
    virtual void on_request(ConstBytes request, MailboxOutbox& outbox) = 0;
    // The master has read the last reply completely; SM1 is free again.
    virtual void on_reply_read(MailboxOutbox& /*outbox*/) {}
    // The mailbox stopped (the slave left PREOP/SAFEOP/OP/BOOT or lost power):
    // forget any transfer in progress.
    virtual void on_stopped() {}
};

}  // namespace ecpair::sim
