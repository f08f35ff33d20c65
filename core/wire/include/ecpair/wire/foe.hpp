#pragma once
// File access over EtherCAT (ETG.1000.6 §5.8): firmware and files through
// the mailbox (type 4). An FoE message follows the mailbox header directly:
//
//   byte 0     OpCode: 1 RRQ (read request), 2 WRQ (write request), 3 DATA,
//              4 ACK, 5 ERR, 6 BUSY
//   byte 1     reserved
//   bytes 2-5  RRQ/WRQ: password (UDINT)   DATA/ACK: packet number (UDINT)
//              ERR: error code (UDINT)     BUSY: done (UINT), entire (UINT)
//   bytes 6..  RRQ/WRQ: the file name      DATA: the file's bytes
//              ERR/BUSY: optional text
//
// The FoE state machine (who sends what when) lives in the client
// (sequencer/foe_client.hpp) and the simulated server (sim/esc foe_server);
// these are only the messages. Names and texts have no terminator on the
// wire: they end with the message (a NUL some slaves append is cut off).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

enum class FoeOpcode : std::uint8_t { Read = 1, Write = 2, Data = 3, Ack = 4, Error = 5, Busy = 6 };

struct FoeReadRequest {
    std::uint32_t password = 0;
    std::string file;
    friend bool operator==(const FoeReadRequest&, const FoeReadRequest&) = default;
};
struct FoeWriteRequest {
    std::uint32_t password = 0;
    std::string file;
    friend bool operator==(const FoeWriteRequest&, const FoeWriteRequest&) = default;
};
// One packet of the file, numbered from 1; a packet shorter than the
// mailbox allows is the last one (an empty one when the file fills the last exactly).
struct FoeData {
    std::uint32_t packet = 0;
    std::vector<std::uint8_t> data;
    friend bool operator==(const FoeData&, const FoeData&) = default;
};
struct FoeAck {
    std::uint32_t packet = 0;  // the DATA packet acknowledged (0: the write request)
    friend bool operator==(const FoeAck&, const FoeAck&) = default;
};
struct FoeError {
    std::uint32_t code = 0;  // foe_error::k*
    std::string text;
    friend bool operator==(const FoeError&, const FoeError&) = default;
};
// The slave cannot take the next packet yet (erasing flash...): the master
// sends the last packet again later. done/entire: progress, for display.
struct FoeBusy {
    std::uint16_t done = 0;
    std::uint16_t entire = 0;
    std::string text;
    friend bool operator==(const FoeBusy&, const FoeBusy&) = default;
};

using FoeMessage = std::variant<FoeReadRequest, FoeWriteRequest, FoeData, FoeAck, FoeError, FoeBusy>;

inline constexpr std::size_t kFoeHeaderSize = 6;

// The message as it follows the mailbox header.
std::vector<std::uint8_t> encode_foe(const FoeMessage& message);
// `in` is the mailbox body (the header's Length bytes). nullopt when it is
// shorter than the 6-byte FoE header or its OpCode is not one of the six.
std::optional<FoeMessage> decode_foe(ConstBytes in);

// FoE error codes (ETG.1000.6 table 92).
namespace foe_error {
inline constexpr std::uint32_t kNotDefined = 0x8000;
inline constexpr std::uint32_t kNotFound = 0x8001;
inline constexpr std::uint32_t kAccessDenied = 0x8002;
inline constexpr std::uint32_t kDiskFull = 0x8003;
inline constexpr std::uint32_t kIllegal = 0x8004;
inline constexpr std::uint32_t kPacketNumberWrong = 0x8005;
inline constexpr std::uint32_t kAlreadyExists = 0x8006;
inline constexpr std::uint32_t kNoUser = 0x8007;
inline constexpr std::uint32_t kBootstrapOnly = 0x8008;
inline constexpr std::uint32_t kNotBootstrap = 0x8009;
inline constexpr std::uint32_t kNoRights = 0x800A;
inline constexpr std::uint32_t kProgramError = 0x800B;
}  // namespace foe_error

// "file not found", "unknown FoE error".
std::string_view foe_error_text(std::uint32_t code);

}  // namespace ecpair::wire
