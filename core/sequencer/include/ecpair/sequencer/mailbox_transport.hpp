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
//
// On top of that, whole messages of one protocol, as every protocol client
// (SDO, SDO Information, FoE, SoE, EoE) uses them: send_message() puts the
// mailbox header (type, next counter) before the payload, after reading
// away a reply left over in SM1; receive_message() waits for the next
// message of the protocol and returns its body. A mailbox error reply ends
// the wait with its detail code. CoE emergencies, which a slave sends
// whenever it likes, never answer anything: they go to the emergency
// handler (or the log) and the wait goes on; a message of another protocol
// is dropped with a debug line.

#include <cstdint>
#include <functional>
#include <stop_token>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/mailbox.hpp"

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
    Timeout,     // SM0 stayed full, or SM1 stayed empty, until the deadline
    TooLong,     // the message does not fit into SM0
    Bus,         // the bus refused (master INACTIVE, cancelled...)
    Stopped,     // the sequencer is shutting down
    ErrorReply,  // the slave answered with a mailbox error reply (error_reply)
    Malformed,   // a reply whose mailbox header does not fit its buffer
};

struct MailboxError {
    MailboxFailure failure = MailboxFailure::Timeout;
    std::optional<bus::BusErrc> bus_error;
    std::uint16_t error_reply = 0;  // ErrorReply: the detail code (wire::mailbox_error_text)
    std::string message;
};

using EmergencyHandler = std::function<void(const wire::CoeEmergency&)>;

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
    // out earlier), so that the next answer read is the answer to the next
    // request. An emergency found there goes to the emergency handler.
    Expected<void, MailboxError> discard_stale_reply(std::stop_token stop);

    // ---- whole messages of one protocol (see the header)
    // A stale reply read away, then `payload` behind a mailbox header of `type` and the next counter.
    Expected<void, MailboxError> send_message(wire::MailboxType type, ConstBytes payload, Clock::time_point deadline,
                                              std::stop_token stop);
    // The body (the header's Length bytes after it) of the next message of `type`.
    Expected<std::vector<std::uint8_t>, MailboxError> receive_message(wire::MailboxType type,
                                                                      Clock::time_point deadline,
                                                                      std::stop_token stop);
    // Where CoE emergencies go; without one they are logged. Set it before the transport is used.
    void set_emergency_handler(EmergencyHandler handler) { emergency_handler_ = std::move(handler); }
    // A whole SM1 buffer read outside a conversation (the mailbox service's
    // poll): an emergency goes to the handler, anything else is dropped with a
    // debug line.
    void dispatch_unsolicited(ConstBytes buffer);

private:
    // nullopt: the buffer held a CoE emergency (handled) or a message of another protocol (dropped).
    Expected<std::optional<std::vector<std::uint8_t>>, MailboxError> take_message(wire::MailboxType type,
                                                                                 ConstBytes buffer);
    // True when `buffer` is a CoE emergency (then handed to the handler).
    bool take_emergency(ConstBytes buffer);
    // One exchange; Timeout/LinkFailure come back as nullopt (poll again), other bus errors as errors.
    Expected<std::optional<bus::DatagramReply>, MailboxError> poll(const bus::DatagramRequest& request);
    Expected<bool, MailboxError> sm1_full();

    bus::BusAccess& bus_;
    Clock& clock_;
    MailboxChannel channel_;
    std::uint8_t counter_ = 0;
    bool drain_before_send_ = false;
    EmergencyHandler emergency_handler_;
};

}  // namespace ecpair::sequencer
