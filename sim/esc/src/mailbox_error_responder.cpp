// Builds the 10-byte error reply on the stack: header + service + detail.

#include "mailbox_error_responder.hpp"

#include <array>

#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sim {

void MailboxErrorResponder::on_request(ConstBytes request, MailboxOutbox& outbox) {
    if (request.size() < wire::MailboxHeader::kSize) return;
    const auto counter = static_cast<std::uint8_t>((request[5] >> 4) & 0x07);
    if (counter != 0 && counter == last_request_counter_) return;  // a retransmission
    last_request_counter_ = counter;

    const auto header = wire::MailboxHeader::decode(request);
    const bool invalid = !header || header->type == wire::MailboxType::Error || header->length == 0;
    reply_counter_ = wire::next_mailbox_counter(reply_counter_);
    std::array<std::uint8_t, wire::MailboxHeader::kSize + wire::MailboxErrorReply::kSize> reply{};
    wire::MailboxHeader{wire::MailboxErrorReply::kSize, 0, 0, 0, wire::MailboxType::Error, reply_counter_}.encode(reply);
    wire::MailboxErrorReply{invalid ? kDetailInvalidHeader : kDetailUnsupportedProtocol}.encode(
        Bytes(reply).subspan(wire::MailboxHeader::kSize));
    outbox.post(reply);
}

void MailboxErrorResponder::on_stopped() {
    last_request_counter_ = 0;
    reply_counter_ = 0;
}

}  // namespace ecpair::sim
