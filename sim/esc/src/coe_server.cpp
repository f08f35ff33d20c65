// The mailbox side of the CoE server: checks the mailbox and CoE headers of
// a request, hands SDO requests to the SdoServer and writes the reply into
// reply_, a buffer as long as SM1, so no reply can be longer than SM1.
// reply_ also keeps the last reply for a retransmitted request and for a
// reply that has to wait until the master read SM1.

#include "ecpair/sim/coe_server.hpp"

#include "ecpair/common/log.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "sdo_information_server.hpp"
#include "sdo_server.hpp"

namespace ecpair::sim {
namespace {

// Mailbox error details (ETG.1000.4), the ones this server sends.
constexpr std::uint16_t kUnsupportedProtocol = 0x0002;
constexpr std::uint16_t kServiceNotSupported = 0x0004;
constexpr std::uint16_t kInvalidHeader = 0x0005;
constexpr std::uint16_t kSizeTooShort = 0x0006;
constexpr std::uint16_t kInvalidSize = 0x0008;

constexpr std::size_t kCoeOverhead = wire::MailboxHeader::kSize + wire::CoeHeader::kSize;

std::size_t sdo_reply_capacity(std::size_t mailbox_in_size) {
    return mailbox_in_size > kCoeOverhead ? mailbox_in_size - kCoeOverhead : 0;
}

std::size_t information_fragment_capacity(std::size_t mailbox_in_size) {
    const std::size_t overhead = kCoeOverhead + wire::SdoInfoHeader::kSize;
    return mailbox_in_size > overhead ? mailbox_in_size - overhead : 0;
}

// Read before the header is checked: a retransmission is one even when its header is bad.
std::uint8_t counter_of(ConstBytes request) { return static_cast<std::uint8_t>((request[5] >> 4) & 0x07); }

}  // namespace

CoeServer::CoeServer(ObjectDictionary dictionary, CoeSlaveContext& slave, std::size_t mailbox_in_size)
    : dictionary_(std::move(dictionary)),
      slave_(slave),
      sdo_(std::make_unique<SdoServer>(dictionary_, slave_, sdo_reply_capacity(mailbox_in_size))),
      information_(std::make_unique<SdoInformationServer>(dictionary_, information_fragment_capacity(mailbox_in_size))),
      reply_(mailbox_in_size) {
    if (mailbox_in_size < kCoeOverhead + wire::SdoMessage::kHeaderSize) {
        logger("esc")->warn("CoE server with an SM1 of {} bytes: too short for any SDO reply", mailbox_in_size);
    }
}

CoeServer::~CoeServer() = default;

void CoeServer::on_request(ConstBytes request, MailboxOutbox& outbox) {
    if (request.size() < wire::MailboxHeader::kSize) return;  // no SM0 is that short
    const std::uint8_t counter = counter_of(request);
    if (counter != 0 && counter == last_request_counter_) {
        logger("esc")->debug("station {:#06x}: mailbox request with counter {} repeated: last reply again",
                             slave_.station_address(), counter);
        if (reply_size_ > 0 && !reply_waiting_) post_reply(outbox);
        return;
    }
    last_request_counter_ = counter;
    information_->reset();  // a new request ends a fragmented SDO Information response

    const auto header = wire::MailboxHeader::decode(request);
    if (!header) return reply_error(kInvalidSize, outbox);  // longer than the mailbox
    if (header->length == 0 || header->type == wire::MailboxType::Error) return reply_error(kInvalidHeader, outbox);
    if (header->type != wire::MailboxType::CoE) return reply_error(kUnsupportedProtocol, outbox);
    // The bootstrap mailbox of BOOT is for FoE; a slave stack offers CoE from PREOP on.
    if (slave_.al_state() == eni::SlaveState::Boot) return reply_error(kUnsupportedProtocol, outbox);
    handle_coe(request.subspan(wire::MailboxHeader::kSize, header->length), outbox);
}

void CoeServer::handle_coe(ConstBytes body, MailboxOutbox& outbox) {
    const auto coe = wire::CoeHeader::decode(body);
    if (!coe) return reply_error(kSizeTooShort, outbox);
    if (coe->service == wire::CoeService::SdoInformation) {
        information_->handle(body.subspan(wire::CoeHeader::kSize));
        return send_information_fragment(outbox);
    }
    if (coe->service != wire::CoeService::SdoRequest) {
        const bool no_service = static_cast<unsigned>(coe->service) == 0;
        return reply_error(no_service ? kInvalidHeader : kServiceNotSupported, outbox);
    }
    const ConstBytes sdo = body.subspan(wire::CoeHeader::kSize);
    if (sdo.size() < wire::SdoMessage::kHeaderSize) return reply_error(kSizeTooShort, outbox);

    const auto request = wire::SdoMessage::decode(sdo, false);
    const std::optional<wire::SdoMessage> reply =
        request ? sdo_->handle(*request)
                : wire::SdoMessage::abort(load_le<std::uint16_t>(sdo, 1), sdo[3], wire::sdo_abort::kUnknownCommand);
    if (!reply) return;

    const std::size_t size = reply->encoded_size();
    if (kCoeOverhead + size > reply_.size()) {
        logger("esc")->debug("station {:#06x}: an SDO reply of {} bytes does not fit SM1 ({} bytes): not sent",
                             slave_.station_address(), kCoeOverhead + size, reply_.size());
        return;
    }
    // An abort is an SDO request of the server (ETG.1000.6), as SOES sends it.
    const auto service = reply->command == wire::SdoCommand::Abort ? wire::CoeService::SdoRequest
                                                                   : wire::CoeService::SdoResponse;
    wire::CoeHeader{0, service}.encode(Bytes(reply_).subspan(wire::MailboxHeader::kSize));
    reply->encode(Bytes(reply_).subspan(kCoeOverhead));
    send(wire::MailboxType::CoE, wire::CoeHeader::kSize + size, outbox);
}

void CoeServer::send_information_fragment(MailboxOutbox& outbox) {
    if (!information_->has_fragment()) return;
    wire::CoeHeader{0, wire::CoeService::SdoInformation}.encode(Bytes(reply_).subspan(wire::MailboxHeader::kSize));
    const std::size_t size = information_->next_fragment(Bytes(reply_).subspan(kCoeOverhead));
    send(wire::MailboxType::CoE, wire::CoeHeader::kSize + size, outbox);
}

void CoeServer::reply_error(std::uint16_t detail, MailboxOutbox& outbox) {
    logger("esc")->debug("station {:#06x}: mailbox error reply {:#06x} ({})", slave_.station_address(), detail,
                         wire::mailbox_error_text(detail));
    if (wire::MailboxHeader::kSize + wire::MailboxErrorReply::kSize > reply_.size()) return;
    wire::MailboxErrorReply{detail}.encode(Bytes(reply_).subspan(wire::MailboxHeader::kSize));
    send(wire::MailboxType::Error, wire::MailboxErrorReply::kSize, outbox);
}

void CoeServer::send(wire::MailboxType type, std::size_t payload_size, MailboxOutbox& outbox) {
    if (reply_waiting_) {
        logger("esc")->warn("station {:#06x}: a new request came before the master read the last reply; "
                            "that reply is replaced", slave_.station_address());
    }
    reply_counter_ = wire::next_mailbox_counter(reply_counter_);
    wire::MailboxHeader{static_cast<std::uint16_t>(payload_size), slave_.station_address(), 0, 0, type, reply_counter_}
        .encode(reply_);
    reply_size_ = wire::MailboxHeader::kSize + payload_size;
    reply_waiting_ = true;
    post_reply(outbox);
}

void CoeServer::post_reply(MailboxOutbox& outbox) {
    if (outbox.post(ConstBytes(reply_).first(reply_size_))) reply_waiting_ = false;
}

void CoeServer::on_reply_read(MailboxOutbox& outbox) {
    if (reply_waiting_) {
        post_reply(outbox);
    } else {
        send_information_fragment(outbox);  // the next fragment of an SDO Information response, if any
    }
}

void CoeServer::on_stopped() {
    sdo_->reset();
    information_->reset();
    reply_size_ = 0;
    reply_waiting_ = false;
    last_request_counter_ = 0;
    reply_counter_ = 0;
}

}  // namespace ecpair::sim
