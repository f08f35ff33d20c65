#pragma once
// Every slave's mailbox, as everyone who talks to slaves shares it: the
// state machine's mailbox InitCmds, the mailbox service's requests and its
// poll for emergencies. A slave's mailbox holds one conversation at a time
// (a Session: the slave's MailboxTransport, under the slave's lock) and one
// mailbox counter, so two users never take each other's replies or repeat
// each other's counters; different slaves' mailboxes are independent, so
// conversations with different slaves run side by side (each on its own
// thread, their datagrams packed into the same frames by the acyclic queue).
//
// After a hot takeover, continue_after() hands each slave the counter the
// previous ACTIVE used last; it applies when the slave's next session
// opens (MailboxTransport::continue_after).

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sequencer {

class SlaveMailbox {
public:
    SlaveMailbox(std::size_t slave_index, std::uint16_t protocols, bus::BusAccess& bus, Clock& clock,
                 MailboxChannel channel);

    // The exclusive use of the mailbox while it lives.
    class Session {
    public:
        MailboxTransport& transport() { return mailbox_->transport_; }
        std::size_t slave_index() const { return mailbox_->slave_index_; }

    private:
        friend class SlaveMailbox;
        Session(SlaveMailbox& mailbox, std::unique_lock<std::mutex> lock);
        SlaveMailbox* mailbox_;
        std::unique_lock<std::mutex> lock_;
    };

    // Waits until the conversation under way (if any) ends.
    Session open();
    // nullopt when a conversation is under way.
    std::optional<Session> try_open();

    std::size_t slave_index() const { return slave_index_; }
    // eni::MailboxProtocol bits the ENI gives the slave.
    bool supports(eni::MailboxProtocol protocol) const { return (protocols_ & protocol) != 0; }
    const MailboxChannel& channel() const { return transport_.channel(); }
    // Applied when the next session opens.
    void continue_after(std::uint8_t last_counter);

private:
    friend class SlaveMailboxes;
    void prepare(Session& session);

    const std::size_t slave_index_;
    const std::uint16_t protocols_;
    std::mutex conversation_;  // held by a Session
    MailboxTransport transport_;  // used under conversation_
    std::mutex inherited_mutex_;
    std::optional<std::uint8_t> inherited_counter_;  // guarded by inherited_mutex_
};

class SlaveMailboxes {
public:
    using EmergencyHandler = std::function<void(std::size_t slave_index, const wire::CoeEmergency&)>;

    // One SlaveMailbox per slave of `eni` that has a mailbox (mailbox_channel_of).
    SlaveMailboxes(const eni::EniConfig& eni, bus::BusAccess& bus, Clock& clock = steady_clock());

    // nullptr when the slave (EniConfig::slaves index) has no mailbox.
    SlaveMailbox* find(std::size_t slave_index);
    std::size_t slave_count() const { return mailboxes_.size(); }
    // Per slave in ENI order (0: none seen), after a takeover.
    void continue_after(const std::vector<std::uint8_t>& last_counters);
    // Where every slave's CoE emergencies go (set before any conversation; without one they are logged).
    void set_emergency_handler(EmergencyHandler handler);

private:
    std::vector<std::unique_ptr<SlaveMailbox>> mailboxes_;  // by slave index, null without a mailbox
};

}  // namespace ecpair::sequencer
