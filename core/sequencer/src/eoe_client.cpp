// EoE requests and their responses (see the header). The result code sits
// where fragment data has its fragment word.

#include "ecpair/sequencer/eoe_client.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"

namespace ecpair::sequencer {

Expected<void, ProtocolError> EoeClient::set_ip_parameters(const wire::EoeIpParameters& parameters, std::uint8_t port,
                                                           std::chrono::milliseconds timeout, std::stop_token stop) {
    return set_ip_parameters(parameters.encode(), port, timeout, stop);
}

Expected<void, ProtocolError> EoeClient::set_ip_parameters(ConstBytes request_data, std::uint8_t port,
                                                           std::chrono::milliseconds timeout, std::stop_token stop) {
    const auto parameters = wire::EoeIpParameters::decode(request_data);
    const std::string what =
        fmt::format("EoE set IP parameters ({})", parameters ? parameters->describe() : std::string("undecodable data"));
    auto answer = transact(what, wire::EoeFrameType::SetIpRequest, wire::EoeFrameType::SetIpResponse, port,
                           request_data, timeout, stop);
    if (!answer) return unexpected(std::move(answer).error());
    return {};
}

Expected<wire::EoeIpParameters, ProtocolError> EoeClient::get_ip_parameters(std::uint8_t port,
                                                                            std::chrono::milliseconds timeout,
                                                                            std::stop_token stop) {
    const std::string what = "EoE get IP parameters";
    auto answer = transact(what, wire::EoeFrameType::GetIpRequest, wire::EoeFrameType::GetIpResponse, port, {},
                           timeout, stop);
    if (!answer) return unexpected(std::move(answer).error());
    auto parameters = wire::EoeIpParameters::decode(*answer);
    if (!parameters) return unexpected(protocol_error(ProtocolFailure::Malformed, what, "malformed IP parameters"));
    return std::move(*parameters);
}

Expected<std::vector<std::uint8_t>, ProtocolError> EoeClient::transact(const std::string& what, wire::EoeFrameType type,
                                                                       wire::EoeFrameType answer, std::uint8_t port,
                                                                       ConstBytes data,
                                                                       std::chrono::milliseconds timeout,
                                                                       std::stop_token stop) {
    std::vector<std::uint8_t> message(wire::EoeHeader::kSize + data.size());
    wire::EoeHeader header;
    header.type = type;
    header.port = port;
    header.encode(message);
    std::copy(data.begin(), data.end(), message.begin() + wire::EoeHeader::kSize);
    const auto deadline = clock_.now() + timeout;
    if (auto sent = transport_.send_message(wire::MailboxType::EoE, message, deadline, stop); !sent) {
        return unexpected(protocol_error_from(sent.error(), what));
    }
    for (;;) {
        auto body = transport_.receive_message(wire::MailboxType::EoE, deadline, stop);
        if (!body) return unexpected(protocol_error_from(body.error(), what));
        const auto reply = wire::EoeHeader::decode(*body);
        if (!reply) return unexpected(protocol_error(ProtocolFailure::Malformed, what, "EoE header missing"));
        if (reply->type == wire::EoeFrameType::FragmentData) {
            logger("sequencer")->debug("station {}: dropped an Ethernet fragment from the slave during {}",
                                       transport_.channel().station, what);
            continue;
        }
        if (reply->type != answer) {
            return unexpected(protocol_error(ProtocolFailure::Malformed, what,
                                             fmt::format("EoE frame type {} instead of {}",
                                                         static_cast<unsigned>(reply->type),
                                                         static_cast<unsigned>(answer))));
        }
        if (reply->word != wire::eoe_result::kSuccess) {
            auto e = protocol_error(ProtocolFailure::Refused, what,
                                    fmt::format("the slave answered result 0x{:04x} {}", reply->word,
                                                wire::eoe_result_text(reply->word)));
            e.code = reply->word;
            return unexpected(std::move(e));
        }
        return std::vector<std::uint8_t>(body->begin() + wire::EoeHeader::kSize, body->end());
    }
}

}  // namespace ecpair::sequencer
