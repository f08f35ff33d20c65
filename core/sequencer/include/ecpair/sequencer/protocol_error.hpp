#pragma once
// How a conversation of the FoE, SoE and EoE clients can fail: the slave
// refused with its protocol's own error (an FoE error request, an SoE error
// response, an EoE result other than success), with a mailbox error reply,
// or the mailbox itself failed (timeout, too long, bus refused, stopped).
// The message names the request ("FoE read 'app.bin'") and the reason.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"

namespace ecpair::sequencer {

enum class ProtocolFailure : std::uint8_t {
    Refused,       // the slave's protocol error (code)
    MailboxError,  // a mailbox error reply (mailbox_error)
    Timeout,       // no answer in time, or the mailbox stayed full
    Malformed,     // an answer that is not the expected message
    TooLong,       // the request does not fit, or the answer grew past the limit
    Bus,           // the bus refused (bus_error)
    Stopped,       // shutting down
};

std::string_view to_string(ProtocolFailure failure);

struct ProtocolError {
    ProtocolFailure failure = ProtocolFailure::Timeout;
    std::uint32_t code = 0;           // Refused: FoE error code, SoE error code or EoE result
    std::uint16_t mailbox_error = 0;  // MailboxError
    std::optional<bus::BusErrc> bus_error;
    std::string message;
};

// A mailbox failure under the request that `prefix` names.
ProtocolError protocol_error_from(const MailboxError& error, std::string_view prefix);
ProtocolError protocol_error(ProtocolFailure failure, std::string_view prefix, std::string_view detail);

}  // namespace ecpair::sequencer
