// EoE requests answered from the IP parameters the slave holds (see the header).

#include "ecpair/sim/eoe_server.hpp"

#include <algorithm>
#include <vector>

#include "ecpair/common/log.hpp"

namespace ecpair::sim {

void EoeServer::respond(wire::EoeFrameType type, std::uint8_t port, std::uint16_t result, ConstBytes data,
                        MailboxReplies& replies) {
    std::vector<std::uint8_t> body(wire::EoeHeader::kSize + data.size());
    wire::EoeHeader header;
    header.type = type;
    header.port = port;
    header.word = result;
    header.encode(body);
    std::copy(data.begin(), data.end(), body.begin() + wire::EoeHeader::kSize);
    replies.reply(body);
}

void EoeServer::on_request(ConstBytes body, MailboxReplies& replies) {
    const auto header = wire::EoeHeader::decode(body);
    if (!header) return replies.error(0x0006);  // too short for the EoE header
    const ConstBytes data = body.subspan(wire::EoeHeader::kSize);
    switch (header->type) {
        case wire::EoeFrameType::SetIpRequest: {
            const auto set = wire::EoeIpParameters::decode(data);
            if (!set) {
                return respond(wire::EoeFrameType::SetIpResponse, header->port, wire::eoe_result::kUnspecifiedError, {},
                               replies);
            }
            if (set->mac) parameters_.mac = set->mac;
            if (set->ip) parameters_.ip = set->ip;
            if (set->subnet) parameters_.subnet = set->subnet;
            if (set->gateway) parameters_.gateway = set->gateway;
            if (set->dns_server) parameters_.dns_server = set->dns_server;
            if (set->dns_name) parameters_.dns_name = set->dns_name;
            logger("esc")->info("EoE: IP parameters set: {}", set->describe());
            return respond(wire::EoeFrameType::SetIpResponse, header->port, wire::eoe_result::kSuccess, {}, replies);
        }
        case wire::EoeFrameType::GetIpRequest:
            return respond(wire::EoeFrameType::GetIpResponse, header->port, wire::eoe_result::kSuccess,
                           parameters_.encode(), replies);
        case wire::EoeFrameType::SetFilterRequest:
        case wire::EoeFrameType::GetFilterRequest:
            return respond(static_cast<wire::EoeFrameType>(static_cast<std::uint8_t>(header->type) + 1), header->port,
                           wire::eoe_result::kNoFilterSupport, {}, replies);
        case wire::EoeFrameType::FragmentData:
            logger("esc")->debug("EoE: an Ethernet fragment dropped (no network behind this slave)");
            return;
        default:
            logger("esc")->debug("EoE: frame type {} from the master dropped (not a request)",
                                 static_cast<unsigned>(header->type));
            return;
    }
}

}  // namespace ecpair::sim
