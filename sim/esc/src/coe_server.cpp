// The CoE protocol of the emulated slave stack: checks the CoE header of a
// request, hands SDO requests to the SdoServer and SDO Information requests
// to the SdoInformationServer, and builds each reply in reply_, a buffer as
// long as SM1, so no reply can be longer than SM1.

#include "ecpair/sim/coe_server.hpp"

#include "ecpair/common/log.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "sdo_information_server.hpp"
#include "sdo_server.hpp"

namespace ecpair::sim {
namespace {

// Mailbox error details (ETG.1000.4), the ones this server sends.
constexpr std::uint16_t kServiceNotSupported = 0x0004;
constexpr std::uint16_t kInvalidHeader = 0x0005;
constexpr std::uint16_t kSizeTooShort = 0x0006;

constexpr std::size_t kCoeOverhead = wire::MailboxHeader::kSize + wire::CoeHeader::kSize;

std::size_t sdo_reply_capacity(std::size_t mailbox_in_size) {
    return mailbox_in_size > kCoeOverhead ? mailbox_in_size - kCoeOverhead : 0;
}

std::size_t information_fragment_capacity(std::size_t mailbox_in_size) {
    const std::size_t overhead = kCoeOverhead + wire::SdoInfoHeader::kSize;
    return mailbox_in_size > overhead ? mailbox_in_size - overhead : 0;
}

}  // namespace

CoeServer::CoeServer(ObjectDictionary dictionary, CoeSlaveContext& slave, std::size_t mailbox_in_size)
    : dictionary_(std::move(dictionary)),
      slave_(slave),
      sdo_(std::make_unique<SdoServer>(dictionary_, slave_, sdo_reply_capacity(mailbox_in_size))),
      information_(std::make_unique<SdoInformationServer>(dictionary_, information_fragment_capacity(mailbox_in_size))),
      reply_(mailbox_in_size > wire::MailboxHeader::kSize ? mailbox_in_size - wire::MailboxHeader::kSize : 0) {
    if (mailbox_in_size < kCoeOverhead + wire::SdoMessage::kHeaderSize) {
        logger("esc")->warn("CoE server with an SM1 of {} bytes: too short for any SDO reply", mailbox_in_size);
    }
}

CoeServer::~CoeServer() = default;

void CoeServer::on_request(ConstBytes body, MailboxReplies& replies) {
    const auto coe = wire::CoeHeader::decode(body);
    if (!coe) return replies.error(kSizeTooShort);
    if (coe->service == wire::CoeService::SdoInformation) {
        information_->handle(body.subspan(wire::CoeHeader::kSize));
        return send_information_fragment(replies);
    }
    if (coe->service != wire::CoeService::SdoRequest) {
        const bool no_service = static_cast<unsigned>(coe->service) == 0;
        return replies.error(no_service ? kInvalidHeader : kServiceNotSupported);
    }
    const ConstBytes sdo = body.subspan(wire::CoeHeader::kSize);
    if (sdo.size() < wire::SdoMessage::kHeaderSize) return replies.error(kSizeTooShort);

    const auto request = wire::SdoMessage::decode(sdo, false);
    const std::optional<wire::SdoMessage> reply =
        request ? sdo_->handle(*request)
                : wire::SdoMessage::abort(load_le<std::uint16_t>(sdo, 1), sdo[3], wire::sdo_abort::kUnknownCommand);
    if (!reply) return;

    const std::size_t size = reply->encoded_size();
    if (wire::CoeHeader::kSize + size > reply_.size()) {
        logger("esc")->debug("station {:#06x}: an SDO reply of {} bytes does not fit SM1: not sent",
                             slave_.station_address(), kCoeOverhead + size);
        return;
    }
    // An abort is an SDO request of the server (ETG.1000.6), as SOES sends it.
    const auto service = reply->command == wire::SdoCommand::Abort ? wire::CoeService::SdoRequest
                                                                   : wire::CoeService::SdoResponse;
    wire::CoeHeader{0, service}.encode(reply_);
    reply->encode(Bytes(reply_).subspan(wire::CoeHeader::kSize));
    replies.reply(ConstBytes(reply_).first(wire::CoeHeader::kSize + size));
}

void CoeServer::send_information_fragment(MailboxReplies& replies) {
    if (!information_->has_fragment() || reply_.size() < wire::CoeHeader::kSize + wire::SdoInfoHeader::kSize) return;
    wire::CoeHeader{0, wire::CoeService::SdoInformation}.encode(reply_);
    const std::size_t size = information_->next_fragment(Bytes(reply_).subspan(wire::CoeHeader::kSize));
    replies.reply(ConstBytes(reply_).first(wire::CoeHeader::kSize + size));
}

void CoeServer::on_reply_read(MailboxReplies& replies) { send_information_fragment(replies); }

void CoeServer::end_answer() { information_->reset(); }

void CoeServer::reset() {
    sdo_->reset();
    information_->reset();
}

std::vector<std::uint8_t> CoeServer::emergency(const wire::CoeEmergency& emergency) {
    std::vector<std::uint8_t> body(wire::CoeHeader::kSize + wire::CoeEmergency::kSize);
    wire::CoeHeader{0, wire::CoeService::Emergency}.encode(body);
    emergency.encode(Bytes(body).subspan(wire::CoeHeader::kSize));
    return body;
}

}  // namespace ecpair::sim
