#include "ecpair/sequencer/protocol_error.hpp"

#include <fmt/format.h>

namespace ecpair::sequencer {

std::string_view to_string(ProtocolFailure failure) {
    switch (failure) {
        case ProtocolFailure::Refused: return "refused";
        case ProtocolFailure::MailboxError: return "mailbox error";
        case ProtocolFailure::Timeout: return "timeout";
        case ProtocolFailure::Malformed: return "malformed answer";
        case ProtocolFailure::TooLong: return "too long";
        case ProtocolFailure::Bus: return "bus refused";
        case ProtocolFailure::Stopped: return "stopped";
    }
    return "?";
}

ProtocolError protocol_error_from(const MailboxError& e, std::string_view prefix) {
    ProtocolError error;
    switch (e.failure) {
        case MailboxFailure::Timeout: error.failure = ProtocolFailure::Timeout; break;
        case MailboxFailure::TooLong: error.failure = ProtocolFailure::TooLong; break;
        case MailboxFailure::Bus: error.failure = ProtocolFailure::Bus; break;
        case MailboxFailure::Stopped: error.failure = ProtocolFailure::Stopped; break;
        case MailboxFailure::ErrorReply: error.failure = ProtocolFailure::MailboxError; break;
        case MailboxFailure::Malformed: error.failure = ProtocolFailure::Malformed; break;
    }
    error.mailbox_error = e.error_reply;
    error.bus_error = e.bus_error;
    error.message = fmt::format("{}: {}", prefix, e.message);
    return error;
}

ProtocolError protocol_error(ProtocolFailure failure, std::string_view prefix, std::string_view detail) {
    ProtocolError error;
    error.failure = failure;
    error.message = fmt::format("{}: {}", prefix, detail);
    return error;
}

}  // namespace ecpair::sequencer
