#pragma once
// CANopen over EtherCAT (ETG.1000.6 §5.6): the 2-byte CoE header after the
// mailbox header, and the SDO services masters use for InitCmds:
// download/upload, expedited (<= 4 bytes in the command) or normal (size +
// data), CompleteAccess, segments for transfers longer than one mailbox, and
// abort.
//
// Layout of an SDO message (after mailbox header and CoE header):
//   byte 0     command specifier: [7:5] ccs/scs, then per service bits
//   bytes 1-2  index (LE), byte 3 subindex
//   bytes 4-7  expedited data, or the complete size of a normal transfer
//   bytes 8..  data of a normal transfer
// Segment messages have only byte 0 followed by up to the mailbox size of data.

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

enum class CoeService : std::uint8_t {
    Emergency = 1,
    SdoRequest = 2,
    SdoResponse = 3,
    TxPdo = 4,
    RxPdo = 5,
    SdoInformation = 8,
};

struct CoeHeader {
    static constexpr std::size_t kSize = 2;
    std::uint16_t number = 0;  // 9 bits, 0 for SDO
    CoeService service = CoeService::SdoRequest;

    void encode(Bytes out) const;
    static std::optional<CoeHeader> decode(ConstBytes in);
};

// The command specifier's meaning, for requests (ccs) and responses (scs).
enum class SdoCommand : std::uint8_t {
    DownloadSegment,    // ccs 0 request / scs 1 response
    Download,           // ccs 1 initiate download request / scs 3 response
    Upload,             // ccs 2 initiate upload request / scs 2 response
    UploadSegment,      // ccs 3 request / scs 0 response
    Abort,              // 0x80
};

struct SdoMessage {
    static constexpr std::size_t kHeaderSize = 8;   // command, index, subindex, 4 data/size bytes
    static constexpr std::size_t kSegmentHeader = 1;

    SdoCommand command = SdoCommand::Download;
    bool is_response = false;
    bool complete_access = false;
    bool expedited = false;
    bool size_indicated = false;
    bool toggle = false;        // segments
    bool last_segment = false;  // segments: no more follow
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint32_t complete_size = 0;  // normal transfer: total bytes; abort: the abort code
    std::vector<std::uint8_t> data;   // expedited: 1..4 bytes; normal/segment: the bytes carried here

    // Bytes needed by encode().
    std::size_t encoded_size() const;
    void encode(Bytes out) const;
    // `in` starts after the CoE header. nullopt for anything that is not a
    // well-formed SDO message (which also covers every out-of-bounds case).
    static std::optional<SdoMessage> decode(ConstBytes in, bool is_response);

    static SdoMessage abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code);
};

// A CoE emergency (CoE service 1, ETG.1000.6 §5.6.4): an error the slave
// reports on its own, at any time, after the CoE header:
//   bytes 0-1  error code (CiA 301: the high byte's first digit is the class)
//   byte 2     error register (object 0x1001)
//   bytes 3-7  manufacturer-specific data
struct CoeEmergency {
    static constexpr std::size_t kSize = 8;
    std::uint16_t error_code = 0;
    std::uint8_t error_register = 0;
    std::array<std::uint8_t, 5> data{};

    void encode(Bytes out) const;  // out.size() >= kSize
    static std::optional<CoeEmergency> decode(ConstBytes in);
    friend bool operator==(const CoeEmergency&, const CoeEmergency&) = default;
};

// The class of an emergency error code: "current", "temperature", "communication", ...
std::string_view emergency_error_class(std::uint16_t error_code);

// SDO abort codes (ETG.1000.6 table 41) used here and their text.
namespace sdo_abort {
inline constexpr std::uint32_t kToggleBit = 0x05030000;
inline constexpr std::uint32_t kTimeout = 0x05040000;
inline constexpr std::uint32_t kUnknownCommand = 0x05040001;
inline constexpr std::uint32_t kInvalidBlockSize = 0x05040002;
inline constexpr std::uint32_t kInvalidSequenceNumber = 0x05040003;
inline constexpr std::uint32_t kCrcError = 0x05040004;
inline constexpr std::uint32_t kOutOfMemory = 0x05040005;
inline constexpr std::uint32_t kUnsupportedAccess = 0x06010000;
inline constexpr std::uint32_t kWriteOnly = 0x06010001;
inline constexpr std::uint32_t kReadOnly = 0x06010002;
inline constexpr std::uint32_t kSubindexZeroNotZero = 0x06010003;
inline constexpr std::uint32_t kCompleteAccessUnsupported = 0x06010004;
inline constexpr std::uint32_t kObjectDoesNotExist = 0x06020000;
inline constexpr std::uint32_t kCannotMapObject = 0x06040041;
inline constexpr std::uint32_t kPdoLengthExceeded = 0x06040042;
inline constexpr std::uint32_t kParameterIncompatibility = 0x06040043;
inline constexpr std::uint32_t kInternalIncompatibility = 0x06040047;
inline constexpr std::uint32_t kHardwareError = 0x06060000;
inline constexpr std::uint32_t kLengthMismatch = 0x06070010;
inline constexpr std::uint32_t kLengthTooHigh = 0x06070012;
inline constexpr std::uint32_t kLengthTooLow = 0x06070013;
inline constexpr std::uint32_t kSubindexDoesNotExist = 0x06090011;
inline constexpr std::uint32_t kValueOutOfRange = 0x06090030;
inline constexpr std::uint32_t kValueTooHigh = 0x06090031;
inline constexpr std::uint32_t kValueTooLow = 0x06090032;
inline constexpr std::uint32_t kMaximumBelowMinimum = 0x06090036;
inline constexpr std::uint32_t kGeneralError = 0x08000000;
inline constexpr std::uint32_t kCannotStore = 0x08000020;
inline constexpr std::uint32_t kCannotStoreLocalControl = 0x08000021;
inline constexpr std::uint32_t kCannotStoreInState = 0x08000022;
inline constexpr std::uint32_t kNoObjectDictionary = 0x08000023;
inline constexpr std::uint32_t kNoDataAvailable = 0x08000024;
}  // namespace sdo_abort

std::string_view sdo_abort_text(std::uint32_t code);

}  // namespace ecpair::wire
