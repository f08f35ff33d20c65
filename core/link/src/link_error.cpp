// Names of link error codes, for log lines and test output.

#include "ecpair/link/link.hpp"

namespace ecpair::link {

const char* to_string(LinkErrc code) {
    switch (code) {
        case LinkErrc::InterfaceNotFound: return "InterfaceNotFound";
        case LinkErrc::PermissionDenied: return "PermissionDenied";
        case LinkErrc::Closed: return "Closed";
        case LinkErrc::FrameTooLarge: return "FrameTooLarge";
        case LinkErrc::SendFailed: return "SendFailed";
        case LinkErrc::ReceiveFailed: return "ReceiveFailed";
        case LinkErrc::SystemError: return "SystemError";
        case LinkErrc::InterfaceDown: return "InterfaceDown";
    }
    return "Unknown";
}

}  // namespace ecpair::link
