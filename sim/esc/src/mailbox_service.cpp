// SM0 is the master's (ECAT-written) mailbox, SM1 the slave's (ECAT-read)
// one, as in every SOES-like stack; the service only acts while both are
// configured that way, enabled and not deactivated by the PDI.

#include "mailbox_service.hpp"

#include <algorithm>

#include "mailbox_error_responder.hpp"

namespace ecpair::sim {
namespace {

constexpr int kMasterMailbox = 0;  // SM0
constexpr int kSlaveMailbox = 1;   // SM1

}  // namespace

MailboxService::MailboxService(EscMemory& memory, SyncManagerUnit& sync_managers, std::size_t reply_capacity)
    : memory_(memory),
      sync_managers_(sync_managers),
      handler_(std::make_unique<MailboxErrorResponder>()),
      last_reply_(reply_capacity) {}

void MailboxService::set_handler(std::unique_ptr<MailboxHandler> handler) {
    handler_ = handler ? std::move(handler) : std::make_unique<MailboxErrorResponder>();
}

void MailboxService::set_running(bool running) {
    if (running_ && !running) {
        handler_->on_stopped();
        last_reply_size_ = 0;
    }
    running_ = running;
}

bool MailboxService::channels_ready() const {
    const SmChannel& out = sync_managers_.channel(kMasterMailbox);
    const SmChannel& in = sync_managers_.channel(kSlaveMailbox);
    const auto usable = [&](const SmChannel& ch) {
        return ch.active() && ch.mailbox() && !ch.pdi_deactivated && ch.start >= regs::kProcessRam &&
               ch.end() <= memory_.ram_end();
    };
    return usable(out) && out.ecat_writes() && usable(in) && !in.ecat_writes();
}

void MailboxService::after_frame() {
    const SyncManagerUnit::Events events = sync_managers_.take_events();
    if (!running_ || !channels_ready()) return;
    if ((events.read & (1U << kSlaveMailbox)) != 0) handler_->on_reply_read(*this);
    if ((events.written & (1U << kMasterMailbox)) != 0) {
        const SmChannel& out = sync_managers_.channel(kMasterMailbox);
        handler_->on_request(ConstBytes(memory_.bytes()).subspan(out.start, out.length), *this);
        sync_managers_.pdi_mailbox_consumed(kMasterMailbox);
    }
    if (sync_managers_.repeat_requested(kSlaveMailbox)) {
        if (last_reply_size_ > 0) write_reply(ConstBytes(last_reply_).first(last_reply_size_));
        sync_managers_.acknowledge_repeat(kSlaveMailbox);
    }
}

bool MailboxService::post(ConstBytes reply) {
    if (!running_ || !channels_ready() || sync_managers_.mailbox_full(kSlaveMailbox)) return false;
    write_reply(reply);
    const std::size_t kept = std::min(reply.size(), last_reply_.size());
    std::copy_n(reply.begin(), kept, last_reply_.begin());
    last_reply_size_ = kept;
    return true;
}

bool MailboxService::full() const { return sync_managers_.mailbox_full(kSlaveMailbox); }

void MailboxService::write_reply(ConstBytes reply) {
    const SmChannel& in = sync_managers_.channel(kSlaveMailbox);
    Bytes buffer = memory_.bytes().subspan(in.start, in.length);
    const std::size_t copied = std::min(reply.size(), buffer.size());
    std::copy_n(reply.begin(), copied, buffer.begin());
    std::fill(buffer.begin() + static_cast<std::ptrdiff_t>(copied), buffer.end(), std::uint8_t{0});
    sync_managers_.pdi_mailbox_filled(kSlaveMailbox);
}

}  // namespace ecpair::sim
