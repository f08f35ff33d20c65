#pragma once
// Moves whole mailbox messages in and out of one slave's mailbox
// SyncManagers over bus::BusAccess:
//   send:    FPWR of the full SM0 (Send Start, Send Length), the message
//            zero-padded; WKC 0 means the slave has not yet emptied SM0,
//            so the write is repeated (once per poll interval) until the deadline.
//   receive: FPRD of SM1's status byte (0x0808 + 8 + 5 = 0x080D) until bit 3
//            "mailbox full" shows, then FPRD of the full SM1 (Recv Start,
//            Recv Length); a read with WKC 0 found the buffer empty after all.
// The mailbox counter (1..7) of the messages the master sends lives here.

#include <cstdint>
#include <stop_token>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::sequencer {

// Where a slave's mailbox is: its station address and the SM0/SM1 areas.
struct MailboxChannel {
    std::uint16_t station = 0;
    eni::MailboxArea send;  // master -> slave (SM0)
    eni::MailboxArea recv;  // slave -> master (SM1)
};

// A slave's mailbox from its ENI entry: Mailbox/Send and Mailbox/Recv, or
// (Advantech writes no Send/Recv) its Sm0/Sm1 of type MBoxOut/MBoxIn.
// nullopt when the slave has no mailbox.
std::optional<MailboxChannel> mailbox_channel_of(const eni::Slave& slave);

enum class MailboxFailure : std::uint8_t {
    Timeout,   // SM0 stayed full, or SM1 stayed empty, until the deadline
    TooLong,   // the message does not fit into SM0
    Bus,       // the bus refused (master INACTIVE, cancelled...)
    Stopped,   // the sequencer is shutting down
};

struct MailboxError {
    MailboxFailure failure = MailboxFailure::Timeout;
    std::optional<bus::BusErrc> bus_error;
    std::string message;
};

class MailboxTransport {
public:
    MailboxTransport(bus::BusAccess& bus, Clock& clock, MailboxChannel channel);

    const MailboxChannel& channel() const { return channel_; }
    // The counter for the next message the master sends: 1..7, wrapping.
    std::uint8_t next_counter();
    // After a takeover: the previous ACTIVE's last counter to this slave
    // (0: none seen), so that the next message is not taken for its repeat,
    // and a reply to its last request still in SM1 is dropped before the
    // next send (the slave's mailbox must not stay wedged on it).
    void continue_after(std::uint8_t last_counter);

    Expected<void, MailboxError> send(ConstBytes message, Clock::time_point deadline, std::stop_token stop);
    // The whole SM1 buffer (header first); the caller decodes it.
    Expected<std::vector<std::uint8_t>, MailboxError> receive(Clock::time_point deadline, std::stop_token stop);
    // Reads and drops a reply still waiting in SM1 (from a transfer that timed
    // out earlier), so that the next answer read is the answer to the next request.
    Expected<void, MailboxError> discard_stale_reply(std::stop_token stop);

private:
    // One exchange; Timeout/LinkFailure come back as nullopt (poll again), other bus errors as errors.
    Expected<std::optional<bus::DatagramReply>, MailboxError> poll(const bus::DatagramRequest& request);
    Expected<bool, MailboxError> sm1_full();

    bus::BusAccess& bus_;
    Clock& clock_;
    MailboxChannel channel_;
    std::uint8_t counter_ = 0;
    bool drain_before_send_ = false;
};

}  // namespace ecpair::sequencer
