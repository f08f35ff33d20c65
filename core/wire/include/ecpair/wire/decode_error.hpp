#pragma once
// Why a frame could not be decoded, and where (byte offset from the start of
// the Ethernet frame).

#include <cstddef>
#include <cstdint>
#include <string>

namespace ecpair::wire {

enum class DecodeErrc : std::uint8_t {
    TruncatedEthernetHeader,
    NotEtherCat,
    TruncatedEcatHeader,
    UnsupportedEcatType,
    TruncatedDatagramHeader,
    DatagramOverrun,  // the datagram's length runs past the end of the frame
};

struct DecodeError {
    DecodeErrc code;
    std::size_t offset;   // where the problem starts
    std::size_t detail;   // code-specific: the ether type, the declared length...

    std::string describe() const;
};

std::string_view to_string(DecodeErrc code);

}  // namespace ecpair::wire
