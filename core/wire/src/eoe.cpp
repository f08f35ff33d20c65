// EoE header and IP parameter codecs (see the header): fixed offsets,
// little-endian UDINTs, the DNS name NUL-padded to 32 bytes.

#include "ecpair/wire/eoe.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecpair::wire {
namespace {

constexpr std::uint32_t kMacIncluded = 1u << 0;
constexpr std::uint32_t kIpIncluded = 1u << 1;
constexpr std::uint32_t kSubnetIncluded = 1u << 2;
constexpr std::uint32_t kGatewayIncluded = 1u << 3;
constexpr std::uint32_t kDnsServerIncluded = 1u << 4;
constexpr std::uint32_t kDnsNameIncluded = 1u << 5;

constexpr std::size_t kMacOffset = 4;
constexpr std::size_t kIpOffset = 10;
constexpr std::size_t kSubnetOffset = 14;
constexpr std::size_t kGatewayOffset = 18;
constexpr std::size_t kDnsServerOffset = 22;
constexpr std::size_t kDnsNameOffset = 26;

}  // namespace

void EoeHeader::encode(Bytes out) const {
    out[0] = static_cast<std::uint8_t>((static_cast<std::uint8_t>(type) & 0x0F) | ((port & 0x0F) << 4));
    out[1] = static_cast<std::uint8_t>((last_fragment ? 0x01 : 0) | (time_appended ? 0x02 : 0) |
                                       (time_request ? 0x04 : 0));
    store_le<std::uint16_t>(out, 2, word);
}

std::optional<EoeHeader> EoeHeader::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    EoeHeader h;
    h.type = static_cast<EoeFrameType>(in[0] & 0x0F);
    h.port = static_cast<std::uint8_t>(in[0] >> 4);
    h.last_fragment = (in[1] & 0x01) != 0;
    h.time_appended = (in[1] & 0x02) != 0;
    h.time_request = (in[1] & 0x04) != 0;
    h.word = load_le<std::uint16_t>(in, 2);
    return h;
}

std::vector<std::uint8_t> EoeIpParameters::encode() const {
    std::vector<std::uint8_t> out(kEncodedSize, 0);
    std::uint32_t flags = 0;
    if (mac) {
        flags |= kMacIncluded;
        std::copy(mac->bytes.begin(), mac->bytes.end(), out.begin() + kMacOffset);
    }
    const auto put = [&](const std::optional<std::uint32_t>& value, std::uint32_t flag, std::size_t offset) {
        if (!value) return;
        flags |= flag;
        store_le<std::uint32_t>(out, offset, *value);
    };
    put(ip, kIpIncluded, kIpOffset);
    put(subnet, kSubnetIncluded, kSubnetOffset);
    put(gateway, kGatewayIncluded, kGatewayOffset);
    put(dns_server, kDnsServerIncluded, kDnsServerOffset);
    if (dns_name) {
        flags |= kDnsNameIncluded;
        std::copy_n(dns_name->begin(), std::min(dns_name->size(), kDnsNameSize), out.begin() + kDnsNameOffset);
    }
    store_le<std::uint32_t>(out, 0, flags);
    return out;
}

std::optional<EoeIpParameters> EoeIpParameters::decode(ConstBytes in) {
    if (in.size() < 4) return std::nullopt;
    const std::uint32_t flags = load_le<std::uint32_t>(in, 0);
    EoeIpParameters p;
    const auto has = [&](std::uint32_t flag, std::size_t offset, std::size_t size) {
        return (flags & flag) != 0 && offset + size <= in.size();
    };
    const auto cut = [&](std::uint32_t flag, std::size_t offset, std::size_t size) {
        return (flags & flag) != 0 && offset + size > in.size();
    };
    if (cut(kMacIncluded, kMacOffset, 6) || cut(kIpIncluded, kIpOffset, 4) || cut(kSubnetIncluded, kSubnetOffset, 4) ||
        cut(kGatewayIncluded, kGatewayOffset, 4) || cut(kDnsServerIncluded, kDnsServerOffset, 4) ||
        cut(kDnsNameIncluded, kDnsNameOffset, 1)) {
        return std::nullopt;
    }
    if (has(kMacIncluded, kMacOffset, 6)) {
        MacAddress mac;
        std::copy_n(in.begin() + kMacOffset, 6, mac.bytes.begin());
        p.mac = mac;
    }
    if (has(kIpIncluded, kIpOffset, 4)) p.ip = load_le<std::uint32_t>(in, kIpOffset);
    if (has(kSubnetIncluded, kSubnetOffset, 4)) p.subnet = load_le<std::uint32_t>(in, kSubnetOffset);
    if (has(kGatewayIncluded, kGatewayOffset, 4)) p.gateway = load_le<std::uint32_t>(in, kGatewayOffset);
    if (has(kDnsServerIncluded, kDnsServerOffset, 4)) p.dns_server = load_le<std::uint32_t>(in, kDnsServerOffset);
    if ((flags & kDnsNameIncluded) != 0) {
        const auto name = in.subspan(kDnsNameOffset, std::min(kDnsNameSize, in.size() - kDnsNameOffset));
        p.dns_name = std::string(name.begin(), std::find(name.begin(), name.end(), std::uint8_t{0}));
    }
    return p;
}

std::string ipv4_text(std::uint32_t address) {
    return fmt::format("{}.{}.{}.{}", address >> 24, (address >> 16) & 0xFF, (address >> 8) & 0xFF, address & 0xFF);
}

std::string EoeIpParameters::describe() const {
    std::string text;
    const auto add = [&text](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
    if (ip) add("IP " + ipv4_text(*ip));
    if (subnet) add("subnet " + ipv4_text(*subnet));
    if (gateway) add("gateway " + ipv4_text(*gateway));
    if (dns_server) add("DNS server " + ipv4_text(*dns_server));
    if (dns_name) add("DNS name '" + *dns_name + "'");
    if (mac) add("MAC " + mac->to_string());
    return text.empty() ? std::string("nothing") : text;
}

std::string_view eoe_result_text(std::uint16_t result) {
    switch (result) {
        case eoe_result::kSuccess: return "success";
        case eoe_result::kUnspecifiedError: return "unspecified error";
        case eoe_result::kUnsupportedFrameType: return "unsupported frame type";
        case eoe_result::kNoIpSupport: return "no IP support";
        case eoe_result::kDhcpNotSupported: return "DHCP not supported";
        case eoe_result::kNoFilterSupport: return "no filter support";
        default: return "unknown EoE result";
    }
}

}  // namespace ecpair::wire
