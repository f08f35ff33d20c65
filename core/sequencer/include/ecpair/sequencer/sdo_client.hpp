#pragma once
// The CoE SDO client (ETG.1000.6 §5.6.2) over one slave's mailbox:
//   download: expedited (1..4 bytes, not CompleteAccess), normal (size and
//             data in the first message), segmented (what does not fit the
//             first message follows in download segments, toggling);
//   upload:   the answer is expedited or normal, and upload segments are
//             requested while the announced size has not arrived yet.
// CompleteAccess sets the flag in the initiate message (always a normal
// transfer, as SOEM does). Every request waits `timeout` for its answer;
// emergencies arriving meanwhile go to the transport's emergency handler.
// Failures name the object: SDO aborts with their code and text, mailbox
// error replies with theirs, timeouts and malformed answers.
// The client talks through a slave's MailboxTransport, which the caller
// holds for the conversation (SlaveMailbox::Session).

#include <chrono>
#include <cstdint>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sequencer {

enum class SdoFailure : std::uint8_t {
    Abort,         // the slave aborted the transfer (abort_code)
    MailboxError,  // the slave answered with a mailbox error reply (mailbox_error)
    Timeout,       // no answer in time, or the mailbox stayed full
    Protocol,      // an answer that is not the expected SDO response
    TooLong,       // the request cannot be put into the mailbox
    Bus,           // the bus refused (bus_error)
    Stopped,       // the sequencer is shutting down
};

std::string_view to_string(SdoFailure failure);

struct SdoError {
    SdoFailure failure = SdoFailure::Timeout;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint32_t abort_code = 0;     // with Abort
    std::uint16_t mailbox_error = 0;  // with MailboxError
    std::optional<bus::BusErrc> bus_error;
    std::string message;  // "SDO 0x1c12:00 download aborted: 0x06010002 attempt to write a read-only object"
};

// A failure of the mailbox under an SDO or SDO Information transfer, as an
// SdoError about `index`:`subindex` whose message starts with `prefix`.
SdoError sdo_error_from(const MailboxError& error, std::uint16_t index, std::uint8_t subindex,
                        const std::string& prefix);

class SdoClient {
public:
    static constexpr std::chrono::milliseconds kDefaultTimeout{3000};

    SdoClient(MailboxTransport& transport, Clock& clock);

    Expected<void, SdoError> download(std::uint16_t index, std::uint8_t subindex, ConstBytes data,
                                      bool complete_access, std::chrono::milliseconds timeout = kDefaultTimeout,
                                      std::stop_token stop = {});
    Expected<std::vector<std::uint8_t>, SdoError> upload(std::uint16_t index, std::uint8_t subindex,
                                                         bool complete_access,
                                                         std::chrono::milliseconds timeout = kDefaultTimeout,
                                                         std::stop_token stop = {});

private:
    struct Transfer;
    // Sends one SDO request and returns the SDO response to it.
    Expected<wire::SdoMessage, SdoError> transact(const Transfer& transfer, const wire::SdoMessage& request);
    Expected<std::optional<wire::SdoMessage>, SdoError> decode_reply(const Transfer& transfer, ConstBytes body);

    MailboxTransport& transport_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
