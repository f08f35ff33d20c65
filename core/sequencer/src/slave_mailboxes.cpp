#include "ecpair/sequencer/slave_mailboxes.hpp"

namespace ecpair::sequencer {

SlaveMailbox::SlaveMailbox(std::size_t slave_index, std::uint16_t protocols, bus::BusAccess& bus, Clock& clock,
                           MailboxChannel channel)
    : slave_index_(slave_index), protocols_(protocols), transport_(bus, clock, channel) {}

SlaveMailbox::Session::Session(SlaveMailbox& mailbox, std::unique_lock<std::mutex> lock)
    : mailbox_(&mailbox), lock_(std::move(lock)) {}

SlaveMailbox::Session SlaveMailbox::open() {
    Session session(*this, std::unique_lock(conversation_));
    prepare(session);
    return session;
}

std::optional<SlaveMailbox::Session> SlaveMailbox::try_open() {
    std::unique_lock lock(conversation_, std::try_to_lock);
    if (!lock.owns_lock()) return std::nullopt;
    Session session(*this, std::move(lock));
    prepare(session);
    return session;
}

void SlaveMailbox::continue_after(std::uint8_t last_counter) {
    std::lock_guard lock(inherited_mutex_);
    inherited_counter_ = last_counter;
}

void SlaveMailbox::prepare(Session& session) {
    std::optional<std::uint8_t> inherited;
    {
        std::lock_guard lock(inherited_mutex_);
        inherited.swap(inherited_counter_);
    }
    if (inherited) session.transport().continue_after(*inherited);
}

SlaveMailboxes::SlaveMailboxes(const eni::EniConfig& eni, bus::BusAccess& bus, Clock& clock) {
    mailboxes_.resize(eni.slaves.size());
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        const auto& slave = eni.slaves[i];
        const auto channel = mailbox_channel_of(slave);
        if (!channel) continue;
        const std::uint16_t protocols = slave.mailbox ? slave.mailbox->protocols : std::uint16_t{0};
        mailboxes_[i] = std::make_unique<SlaveMailbox>(i, protocols, bus, clock, *channel);
    }
}

SlaveMailbox* SlaveMailboxes::find(std::size_t slave_index) {
    return slave_index < mailboxes_.size() ? mailboxes_[slave_index].get() : nullptr;
}

void SlaveMailboxes::continue_after(const std::vector<std::uint8_t>& last_counters) {
    for (std::size_t i = 0; i < last_counters.size() && i < mailboxes_.size(); ++i) {
        if (mailboxes_[i]) mailboxes_[i]->continue_after(last_counters[i]);
    }
}

void SlaveMailboxes::set_emergency_handler(EmergencyHandler handler) {
    for (auto& mailbox : mailboxes_) {
        if (!mailbox) continue;
        mailbox->transport_.set_emergency_handler(
            [handler, slave = mailbox->slave_index_](const wire::CoeEmergency& e) { handler(slave, e); });
    }
}

}  // namespace ecpair::sequencer
