#pragma once
// The FoE client (ETG.1000.6 §5.8): files to and from one slave over its
// mailbox, the master's half of the FoE state machine.
//
//   read:  RRQ(password, name) -> DATA(1) -> ACK(1) -> DATA(2) -> ... until a
//          DATA shorter than the slave's mailbox allows (SM1 length - 12),
//          which is acknowledged and ends the file (a file that fills its last
//          packet exactly ends with an empty DATA).
//   write: WRQ(password, name) -> ACK(0) -> DATA(1) -> ACK(1) -> ... DATA
//          packets as long as SM0 allows (SM0 length - 12), the last one
//          shorter (empty when the file fills the last packet exactly).
// BUSY from the slave (flash being erased...): the master waits a little and
// sends its last message again, for as long as the slave keeps answering
// within the timeout. ERR from the slave ends the transfer with its code and
// text; a packet number other than the one expected ends it with an ERR
// (0x8005) sent to the slave; a file growing past `max_size` ends a read
// with an ERR (0x8003 disk full) sent to the slave.

#include <chrono>
#include <cstdint>
#include <stop_token>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/sequencer/protocol_error.hpp"
#include "ecpair/wire/foe.hpp"

namespace ecpair::sequencer {

class FoeClient {
public:
    // How long the master waits after a BUSY before it sends its message again.
    static constexpr std::chrono::milliseconds kBusyRetryDelay{10};

    FoeClient(MailboxTransport& transport, Clock& clock) : transport_(transport), clock_(clock) {}

    Expected<std::vector<std::uint8_t>, ProtocolError> read(const std::string& file, std::uint32_t password,
                                                            std::size_t max_size, std::chrono::milliseconds timeout,
                                                            std::stop_token stop = {});
    Expected<void, ProtocolError> write(const std::string& file, std::uint32_t password, ConstBytes data,
                                        std::chrono::milliseconds timeout, std::stop_token stop = {});

private:
    struct Transfer;
    // Sends `message` and returns the slave's answer; BUSY answers are waited out (message sent again).
    Expected<wire::FoeMessage, ProtocolError> exchange(const Transfer& transfer, const wire::FoeMessage& message);
    Expected<wire::FoeMessage, ProtocolError> receive(const Transfer& transfer, Clock::time_point deadline);
    // Tells the slave why the master gives up (best effort) and returns the error.
    ProtocolError abandon(const Transfer& transfer, std::uint32_t code, const std::string& why);

    MailboxTransport& transport_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
