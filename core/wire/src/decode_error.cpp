#include "ecpair/wire/decode_error.hpp"

#include <fmt/format.h>

namespace ecpair::wire {

std::string_view to_string(DecodeErrc code) {
    switch (code) {
        case DecodeErrc::TruncatedEthernetHeader: return "truncated Ethernet header";
        case DecodeErrc::NotEtherCat: return "not an EtherCAT frame";
        case DecodeErrc::TruncatedEcatHeader: return "truncated EtherCAT header";
        case DecodeErrc::UnsupportedEcatType: return "EtherCAT header type is not 1 (datagrams)";
        case DecodeErrc::TruncatedDatagramHeader: return "truncated datagram header";
        case DecodeErrc::DatagramOverrun: return "datagram runs past the end of the frame";
    }
    return "unknown decode error";
}

std::string DecodeError::describe() const {
    switch (code) {
        case DecodeErrc::NotEtherCat:
            return fmt::format("{} (ether type 0x{:04x}) at offset {}", to_string(code), detail, offset);
        case DecodeErrc::UnsupportedEcatType:
            return fmt::format("{} (type {}) at offset {}", to_string(code), detail, offset);
        case DecodeErrc::DatagramOverrun:
            return fmt::format("{}: datagram at offset {} declares {} data bytes", to_string(code), offset,
                               detail);
        default:
            return fmt::format("{} at offset {}", to_string(code), offset);
    }
}

}  // namespace ecpair::wire
