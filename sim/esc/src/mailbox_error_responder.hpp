#pragma once
// The mailbox handler of a slave stack that implements no mailbox protocol,
// as SOES answers unknown requests (ESC_xoeprocess): every request gets a
// mailbox error reply (type 0, service 0x0001) with detail 0x0005 "invalid
// header" for a request of type 0, of length 0 or longer than the mailbox,
// and 0x0002 "unsupported protocol" otherwise. A request repeating the
// previous non-zero counter is a retransmission and is dropped. Replies
// count 1..7.

#include <cstdint>

#include "ecpair/sim/mailbox.hpp"

namespace ecpair::sim {

class MailboxErrorResponder final : public MailboxHandler {
public:
    static constexpr std::uint16_t kDetailUnsupportedProtocol = 0x0002;
    static constexpr std::uint16_t kDetailInvalidHeader = 0x0005;

    void on_request(ConstBytes request, MailboxOutbox& outbox) override;
    void on_stopped() override;

private:
    std::uint8_t last_request_counter_ = 0;
    std::uint8_t reply_counter_ = 0;
};

}  // namespace ecpair::sim
