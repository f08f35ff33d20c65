#pragma once
// Reports link up/down changes of kernel network interfaces as they happen.
//
// A NETLINK_ROUTE socket subscribed to RTMGRP_LINK: the kernel sends an
// RTM_NEWLINK whenever an interface's flags or operational state change and
// an RTM_DELLINK when it disappears. open() first asks for a dump of every
// interface so that is_up() knows the initial state; read_changes() then
// reports only transitions (up -> down, down -> up) of watched interfaces,
// each logged. If the kernel had to drop notifications (socket buffer
// overrun), the monitor asks for a new dump and reports the differences.
//
// The socket belongs to the network namespace of the thread that calls
// open(), and keeps watching that namespace whatever thread reads it.

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "ecpair/link/link_state_source.hpp"

namespace ecpair::link {

namespace detail {
struct LinkMessage;
}

class LinkStateMonitor final : public LinkStateSource {
public:
    // Watches the named interfaces; every interface when `interfaces` is empty.
    static Expected<std::unique_ptr<LinkStateMonitor>, LinkError> open(std::vector<std::string> interfaces = {});
    ~LinkStateMonitor() override;

    int selectable_fd() const override { return socket_; }
    std::vector<LinkStateChange> read_changes() override;
    std::optional<bool> is_up(const std::string& interface) const override;

private:
    explicit LinkStateMonitor(int socket, std::set<std::string> watched);

    using States = std::map<std::string, bool>;  // watched interfaces that exist
    enum class ReadResult : std::uint8_t { Datagram, NothingWaiting, NotificationsLost, Failed };

    // Dumps all interfaces and makes the answers the known states; differing
    // states are appended to `changes`.
    Expected<void, LinkError> synchronise(std::vector<LinkStateChange>& changes);
    // Applies every datagram waiting to the known states. False when the
    // kernel dropped notifications or sent something unreadable.
    bool drain(std::vector<LinkStateChange>& changes);
    // One datagram into buffer_ (its size into `size`), without blocking.
    ReadResult read_datagram(std::size_t& size);
    // Applies one link message to `states` when it names a watched interface.
    void apply(const detail::LinkMessage& message, States& states) const;
    // Appends (and logs) a change for each interface whose state differs.
    static void report_differences(const States& before, const States& after, std::vector<LinkStateChange>& changes);

    int socket_;
    std::set<std::string> watched_;  // empty: all
    States states_;
    std::vector<std::uint8_t> buffer_;  // one datagram
    std::uint32_t sequence_ = 0;
};

}  // namespace ecpair::link
