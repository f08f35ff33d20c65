#pragma once
// Servo drive profile over EtherCAT (ETG.1000.6 §5.9, IEC 61800-7-304):
// IDN parameters of Sercos-profile drives through the mailbox (type 5). An
// SoE message follows the mailbox header:
//
//   byte 0     [2:0] OpCode (1 read request, 2 read response, 3 write
//              request, 4 write response, 5 notification, 6 slave info),
//              [3] incomplete (more fragments follow), [4] error, [7:5] drive number
//   byte 1     the elements addressed: b0 data state, b1 name, b2 attribute,
//              b3 unit, b4 minimum, b5 maximum, b6 value, b7 default
//   bytes 2-3  the IDN, or (incomplete) the fragments left after this one
//   bytes 4..  the element's data; an error response: the 2-byte error code
//
// IDNs: S-0-nnnn is nnnn, P-0-nnnn is 0x8000 + nnnn (bit 15 product-specific,
// bits 14:12 the parameter set).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

enum class SoeOpcode : std::uint8_t {
    ReadRequest = 1,
    ReadResponse = 2,
    WriteRequest = 3,
    WriteResponse = 4,
    Notification = 5,
    SlaveInfo = 6,
};

namespace soe_elements {
inline constexpr std::uint8_t kDataState = 0x01;
inline constexpr std::uint8_t kName = 0x02;
inline constexpr std::uint8_t kAttribute = 0x04;
inline constexpr std::uint8_t kUnit = 0x08;
inline constexpr std::uint8_t kMinimum = 0x10;
inline constexpr std::uint8_t kMaximum = 0x20;
inline constexpr std::uint8_t kValue = 0x40;
inline constexpr std::uint8_t kDefault = 0x80;
}  // namespace soe_elements

struct SoeHeader {
    static constexpr std::size_t kSize = 4;
    SoeOpcode opcode = SoeOpcode::ReadRequest;
    bool incomplete = false;
    bool error = false;
    std::uint8_t drive = 0;     // 0..7
    std::uint8_t elements = soe_elements::kValue;
    std::uint16_t idn_or_fragments = 0;

    void encode(Bytes out) const;  // out.size() >= kSize
    static std::optional<SoeHeader> decode(ConstBytes in);
};

// "S-0-0015" / "P-0-0100" (with its parameter set when not 0: "S-1-0015").
std::string idn_text(std::uint16_t idn);

// SoE error codes (IEC 61800-7-304); the ones drives send most.
std::string_view soe_error_text(std::uint16_t code);

}  // namespace ecpair::wire
