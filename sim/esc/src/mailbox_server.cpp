// The mailbox layer of an emulated slave stack (see the header): header
// checks, retransmissions, the reply counter and the queue of messages
// waiting for SM1. The protocols only see bodies.

#include "ecpair/sim/mailbox_server.hpp"

#include <algorithm>

#include "ecpair/common/log.hpp"

namespace ecpair::sim {
namespace {

// Mailbox error details (ETG.1000.4), the ones the mailbox layer sends.
constexpr std::uint16_t kUnsupportedProtocol = 0x0002;
constexpr std::uint16_t kInvalidHeader = 0x0005;
constexpr std::uint16_t kInvalidSize = 0x0008;

// Read before the header is checked: a retransmission is one even when its header is bad.
std::uint8_t counter_of(ConstBytes request) { return static_cast<std::uint8_t>((request[5] >> 4) & 0x07); }

}  // namespace

class MailboxServer::Replies final : public MailboxReplies {
public:
    Replies(MailboxServer& server, wire::MailboxType type) : server_(server), type_(type) {}

    void reply(ConstBytes body) override {
        if (body.size() > capacity()) {
            logger("esc")->debug("station {:#06x}: a reply of {} bytes does not fit SM1 ({} bytes): not sent",
                                 server_.slave_.station_address(), wire::MailboxHeader::kSize + body.size(),
                                 server_.mailbox_in_size_);
            return;
        }
        server_.queue(type_, body);
    }
    void error(std::uint16_t detail) override {
        logger("esc")->debug("station {:#06x}: mailbox error reply {:#06x} ({})", server_.slave_.station_address(),
                             detail, wire::mailbox_error_text(detail));
        if (capacity() < wire::MailboxErrorReply::kSize) return;
        std::array<std::uint8_t, wire::MailboxErrorReply::kSize> body{};
        wire::MailboxErrorReply{detail}.encode(body);
        server_.queue(wire::MailboxType::Error, body);
    }
    std::size_t capacity() const override {
        return server_.mailbox_in_size_ > wire::MailboxHeader::kSize
                   ? server_.mailbox_in_size_ - wire::MailboxHeader::kSize
                   : 0;
    }

private:
    MailboxServer& server_;
    wire::MailboxType type_;
};

MailboxServer::MailboxServer(MailboxSlave& slave, std::size_t mailbox_in_size,
                             std::vector<std::unique_ptr<MailboxProtocol>> protocols)
    : slave_(slave), mailbox_in_size_(mailbox_in_size), protocols_(std::move(protocols)) {}

MailboxServer::~MailboxServer() = default;

MailboxProtocol* MailboxServer::protocol(wire::MailboxType type) {
    const auto found = std::find_if(protocols_.begin(), protocols_.end(),
                                    [type](const auto& p) { return p->type() == type; });
    return found == protocols_.end() ? nullptr : found->get();
}

void MailboxServer::on_request(ConstBytes request, MailboxOutbox& outbox) {
    if (request.size() < wire::MailboxHeader::kSize) return;  // no SM0 is that short
    const std::uint8_t counter = counter_of(request);
    if (counter != 0 && counter == last_request_counter_) {
        logger("esc")->debug("station {:#06x}: mailbox request with counter {} repeated: last reply again",
                             slave_.station_address(), counter);
        if (!last_reply_.empty() && waiting_.empty()) (void)outbox.post(last_reply_);
        return;
    }
    last_request_counter_ = counter;
    for (auto& p : protocols_) p->end_answer();
    last_answered_ = nullptr;

    const auto header = wire::MailboxHeader::decode(request);
    Replies errors(*this, wire::MailboxType::Error);
    if (!header) {
        errors.error(kInvalidSize);  // longer than the mailbox
    } else if (header->length == 0 || header->type == wire::MailboxType::Error) {
        errors.error(kInvalidHeader);
    } else if (auto* server = protocol(header->type); server == nullptr || !server->serves_in(slave_.al_state())) {
        errors.error(kUnsupportedProtocol);
    } else {
        Replies replies(*this, header->type);
        server->on_request(request.subspan(wire::MailboxHeader::kSize, header->length), replies);
        last_answered_ = server;
    }
    post_next(outbox);
}

void MailboxServer::on_reply_read(MailboxOutbox& outbox) {
    if (waiting_.empty() && last_answered_ != nullptr) {
        Replies replies(*this, last_answered_->type());
        last_answered_->on_reply_read(replies);
    }
    post_next(outbox);
}

void MailboxServer::on_stopped() {
    for (auto& p : protocols_) p->reset();
    waiting_.clear();
    last_reply_.clear();
    last_answered_ = nullptr;
    last_request_counter_ = 0;
    reply_counter_ = 0;
}

bool MailboxServer::send_unsolicited(wire::MailboxType type, ConstBytes body, MailboxOutbox& outbox) {
    if (waiting_.size() >= kMaxQueued || wire::MailboxHeader::kSize + body.size() > mailbox_in_size_) return false;
    queue(type, body);
    post_next(outbox);
    return true;
}

void MailboxServer::queue(wire::MailboxType type, ConstBytes body) {
    if (waiting_.size() >= kMaxQueued) {
        logger("esc")->warn("station {:#06x}: {} mailbox messages wait for the master to read SM1: one more dropped",
                            slave_.station_address(), waiting_.size());
        return;
    }
    reply_counter_ = wire::next_mailbox_counter(reply_counter_);
    std::vector<std::uint8_t> message(wire::MailboxHeader::kSize + body.size());
    wire::MailboxHeader{static_cast<std::uint16_t>(body.size()), slave_.station_address(), 0, 0, type, reply_counter_}
        .encode(message);
    std::copy(body.begin(), body.end(), message.begin() + wire::MailboxHeader::kSize);
    waiting_.push_back(std::move(message));
}

void MailboxServer::post_next(MailboxOutbox& outbox) {
    if (waiting_.empty() || !outbox.post(waiting_.front())) return;
    last_reply_ = std::move(waiting_.front());
    waiting_.pop_front();
}

}  // namespace ecpair::sim
