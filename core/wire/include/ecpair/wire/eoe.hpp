#pragma once
// Ethernet over EtherCAT (ETG.1000.6 §5.7), the part a master needs to
// configure a slave's IP stack: the ENI's EoE InitCmds are "set IP
// parameter" requests. An EoE message follows the mailbox header (type 2):
//
//   byte 0     [3:0] frame type, [7:4] port
//   byte 1     [0] last fragment, [1] time appended, [2] time request
//   bytes 2-3  fragment data: [5:0] fragment, [11:6] offset/size, [15:12] frame;
//              the responses of types 3, 5, 7, 9: the result code
//   bytes 4..  the frame type's data
//
// Set IP parameter (type 2) and get IP parameter response (type 7) carry
// the IP parameters in a fixed layout, each field present whether its flag
// says "included" or not:
//   flags (UDINT: b0 MAC, b1 IP address, b2 subnet mask, b3 default gateway,
//   b4 DNS server, b5 DNS name), MAC (6), IP (UDINT), subnet (UDINT),
//   gateway (UDINT), DNS server (UDINT), DNS name (32 bytes, NUL-padded).
// Addresses are UDINTs on the wire (little-endian): 192.168.1.4 is 0xC0A80104,
// bytes 04 01 A8 C0 (as the ENIs write them).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::wire {

enum class EoeFrameType : std::uint8_t {
    FragmentData = 0,
    InitResponseTimestamp = 1,
    SetIpRequest = 2,
    SetIpResponse = 3,
    SetFilterRequest = 4,
    SetFilterResponse = 5,
    GetIpRequest = 6,
    GetIpResponse = 7,
    GetFilterRequest = 8,
    GetFilterResponse = 9,
};

struct EoeHeader {
    static constexpr std::size_t kSize = 4;
    EoeFrameType type = EoeFrameType::SetIpRequest;
    std::uint8_t port = 0;
    bool last_fragment = true;
    bool time_appended = false;
    bool time_request = false;
    std::uint16_t word = 0;  // fragment/offset/frame of fragment data, the result code of a response

    void encode(Bytes out) const;  // out.size() >= kSize
    static std::optional<EoeHeader> decode(ConstBytes in);
};

struct EoeIpParameters {
    static constexpr std::size_t kEncodedSize = 58;
    static constexpr std::size_t kDnsNameSize = 32;

    std::optional<MacAddress> mac;
    std::optional<std::uint32_t> ip;
    std::optional<std::uint32_t> subnet;
    std::optional<std::uint32_t> gateway;
    std::optional<std::uint32_t> dns_server;
    std::optional<std::string> dns_name;

    std::vector<std::uint8_t> encode() const;
    // nullopt when shorter than the flags, or a field the flags include is cut off.
    static std::optional<EoeIpParameters> decode(ConstBytes in);
    // "IP 192.168.1.4, subnet 255.255.255.0, gateway 192.168.1.10, MAC 10:18:9e:ff:01:04" ("nothing" when empty).
    std::string describe() const;
    friend bool operator==(const EoeIpParameters&, const EoeIpParameters&) = default;
};

// "192.168.1.4" for 0xC0A80104.
std::string ipv4_text(std::uint32_t address);

namespace eoe_result {
inline constexpr std::uint16_t kSuccess = 0x0000;
inline constexpr std::uint16_t kUnspecifiedError = 0x0001;
inline constexpr std::uint16_t kUnsupportedFrameType = 0x0002;
inline constexpr std::uint16_t kNoIpSupport = 0x0201;
inline constexpr std::uint16_t kDhcpNotSupported = 0x0202;
inline constexpr std::uint16_t kNoFilterSupport = 0x0401;
}  // namespace eoe_result

std::string_view eoe_result_text(std::uint16_t result);

}  // namespace ecpair::wire
