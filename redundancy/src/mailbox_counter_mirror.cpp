#include "mailbox_counter_mirror.hpp"

#include <algorithm>

#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::redundancy {

MailboxCounterMirror::MailboxCounterMirror(const eni::EniConfig& eni)
    : counters_(std::make_unique<std::atomic<std::uint8_t>[]>(eni.slaves.size())), slave_count_(eni.slaves.size()) {
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        counters_[i].store(0);
        if (const auto channel = sequencer::mailbox_channel_of(eni.slaves[i])) {
            mailboxes_.push_back({i, wire::DatagramHeader::physical(channel->station, channel->send.start)});
        }
    }
}

void MailboxCounterMirror::observe(const wire::ConstFrameView& frame) {
    for (const auto d : frame) {
        if (d.command() != wire::Command::Fpwr || d.length() < wire::MailboxHeader::kSize) continue;
        const auto it = std::find_if(mailboxes_.begin(), mailboxes_.end(),
                                     [&d](const Mailbox& m) { return m.address == d.address(); });
        if (it == mailboxes_.end()) continue;
        const auto header = wire::MailboxHeader::decode(d.data());
        if (header && header->counter != 0) counters_[it->slave].store(header->counter, std::memory_order_relaxed);
    }
}

std::vector<std::uint8_t> MailboxCounterMirror::counters() const {
    std::vector<std::uint8_t> out(slave_count_);
    for (std::size_t i = 0; i < slave_count_; ++i) out[i] = counters_[i].load(std::memory_order_relaxed);
    return out;
}

}  // namespace ecpair::redundancy
