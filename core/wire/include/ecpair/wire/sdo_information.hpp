#pragma once
// CoE SDO Information (ETG.1000.6 §5.6.3): how a master walks a slave's
// object dictionary. It travels with CoE service 8 after the CoE header:
//
//   byte 0     opcode [6:0], b7 "incomplete" (more fragments follow)
//   byte 1     reserved
//   bytes 2-3  fragments left (after this one)
//   bytes 4..  the service data
//
//   opcode  request (master)                 response (slave)
//   1 / 2   Get OD List: list type (UINT)    list type, then UINT indices (type 0: five counts)
//   3 / 4   Get Object Description: index    index, data type, max subindex, object code, name
//   5 / 6   Get Entry Description: index,    index, subindex, value info, data type, bit length,
//           subindex, value info             object access, [unit, default, min, max,] name
//   7       SDO Info Error: an abort code (UDINT)
//
// A response longer than one mailbox is cut into fragments that the slave
// sends one after the other; the service data of the fragments joined give
// the whole response (the first carries the list type of an OD list).

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

enum class SdoInfoOpcode : std::uint8_t {
    OdListRequest = 1,
    OdListResponse = 2,
    ObjectDescriptionRequest = 3,
    ObjectDescriptionResponse = 4,
    EntryDescriptionRequest = 5,
    EntryDescriptionResponse = 6,
    Error = 7,
};

struct SdoInfoHeader {
    static constexpr std::size_t kSize = 4;
    SdoInfoOpcode opcode = SdoInfoOpcode::OdListRequest;
    bool incomplete = false;
    std::uint16_t fragments_left = 0;

    void encode(Bytes out) const;  // out.size() >= kSize
    static std::optional<SdoInfoHeader> decode(ConstBytes in);
};

// Get OD List list types.
enum class OdListType : std::uint16_t {
    Counts = 0,        // the number of objects of each of the types below
    All = 1,
    RxPdoMappable = 2,
    TxPdoMappable = 3,
    Backup = 4,        // stored for device replacement
    Settings = 5,      // startup parameters
};

// CANopen object codes of an object description.
inline constexpr std::uint8_t kObjectCodeVariable = 7;
inline constexpr std::uint8_t kObjectCodeArray = 8;
inline constexpr std::uint8_t kObjectCodeRecord = 9;

// Object access bits of an entry description.
namespace object_access {
inline constexpr std::uint16_t kReadPreop = 0x0001;
inline constexpr std::uint16_t kReadSafeop = 0x0002;
inline constexpr std::uint16_t kReadOp = 0x0004;
inline constexpr std::uint16_t kWritePreop = 0x0008;
inline constexpr std::uint16_t kWriteSafeop = 0x0010;
inline constexpr std::uint16_t kWriteOp = 0x0020;
inline constexpr std::uint16_t kRxPdoMappable = 0x0040;
inline constexpr std::uint16_t kTxPdoMappable = 0x0080;
}  // namespace object_access

struct OdListRequest {
    OdListType list_type = OdListType::All;
    friend bool operator==(const OdListRequest&, const OdListRequest&) = default;
};
struct ObjectDescriptionRequest {
    std::uint16_t index = 0;
    friend bool operator==(const ObjectDescriptionRequest&, const ObjectDescriptionRequest&) = default;
};
struct EntryDescriptionRequest {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t value_info = 0;  // b3 unit, b4 default, b5 minimum, b6 maximum wanted
    friend bool operator==(const EntryDescriptionRequest&, const EntryDescriptionRequest&) = default;
};
// The master gives up a transfer (or reports an error).
struct SdoInfoErrorRequest {
    std::uint32_t abort_code = 0;
    friend bool operator==(const SdoInfoErrorRequest&, const SdoInfoErrorRequest&) = default;
};
using SdoInfoRequest = std::variant<OdListRequest, ObjectDescriptionRequest, EntryDescriptionRequest, SdoInfoErrorRequest>;

// What a request failed to decode for, with the byte offset (after the CoE header) where it did.
struct SdoInfoDecodeError {
    std::size_t offset = 0;
    std::string what;
};

// `in` starts after the CoE header; one unfragmented request.
std::variant<SdoInfoRequest, SdoInfoDecodeError> decode_sdo_info_request(ConstBytes in);
// The service data of a request (header included), for masters and tests.
std::vector<std::uint8_t> encode_sdo_info_request(const SdoInfoRequest& request);

// ---- responses: the service data after the SDO Info header (all fragments joined)

struct OdListResponse {
    OdListType list_type = OdListType::All;
    std::vector<std::uint16_t> indices;  // Counts: the five counts in list type order

    std::vector<std::uint8_t> encode() const;
    static std::optional<OdListResponse> decode(ConstBytes in);
};

struct ObjectDescription {
    std::uint16_t index = 0;
    std::uint16_t data_type = 0;
    std::uint8_t max_subindex = 0;
    std::uint8_t object_code = kObjectCodeVariable;
    std::string name;

    std::vector<std::uint8_t> encode() const;
    static std::optional<ObjectDescription> decode(ConstBytes in);
};

struct EntryDescription {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t value_info = 0;  // what follows the fixed part; this codec carries none of unit/default/min/max
    std::uint16_t data_type = 0;
    std::uint16_t bit_length = 0;
    std::uint16_t object_access = 0;
    std::string name;

    std::vector<std::uint8_t> encode() const;
    static std::optional<EntryDescription> decode(ConstBytes in);
};

struct SdoInfoError {
    std::uint32_t abort_code = 0;

    std::vector<std::uint8_t> encode() const;
    static std::optional<SdoInfoError> decode(ConstBytes in);
};

// CoE base data type indices (ETG.1000.6 table 64) the simulator describes.
namespace coe_type {
inline constexpr std::uint16_t kBoolean = 0x0001;
inline constexpr std::uint16_t kInteger8 = 0x0002;
inline constexpr std::uint16_t kInteger16 = 0x0003;
inline constexpr std::uint16_t kInteger32 = 0x0004;
inline constexpr std::uint16_t kUnsigned8 = 0x0005;
inline constexpr std::uint16_t kUnsigned16 = 0x0006;
inline constexpr std::uint16_t kUnsigned32 = 0x0007;
inline constexpr std::uint16_t kReal32 = 0x0008;
inline constexpr std::uint16_t kVisibleString = 0x0009;
inline constexpr std::uint16_t kOctetString = 0x000A;
inline constexpr std::uint16_t kInteger24 = 0x0010;
inline constexpr std::uint16_t kReal64 = 0x0011;
inline constexpr std::uint16_t kInteger64 = 0x0015;
inline constexpr std::uint16_t kUnsigned24 = 0x0016;
inline constexpr std::uint16_t kUnsigned64 = 0x001B;
inline constexpr std::uint16_t kPdoMapping = 0x0021;
inline constexpr std::uint16_t kIdentity = 0x0023;
inline constexpr std::uint16_t kBit1 = 0x0030;
}  // namespace coe_type

}  // namespace ecpair::wire
