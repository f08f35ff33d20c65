// LinkStateMonitor: known states are a map from interface name to up/down,
// holding only watched interfaces that exist (a missing one counts as down).
// Every notification is applied to a copy of the map and the differences
// become LinkStateChanges; a dump (at open, or after lost notifications)
// builds a fresh map from scratch and is compared the same way. One rule
// decides "up" for every message: LinkMessage::is_up().
//
// Only datagrams sent by the kernel (netlink port id 0) are read.

#include "ecpair/link/link_state_monitor.hpp"

#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "netlink_link_messages.hpp"
#include "wait_readable.hpp"

namespace ecpair::link {
namespace {

// Large enough for any rtnetlink datagram (dumps use at most 32 KiB).
constexpr std::size_t kDatagramCapacity = 64 * 1024;
// How long open() (or a resync) waits for the kernel to finish a dump.
constexpr std::chrono::seconds kDumpTimeout{2};
// Dump attempts when notifications keep being lost during the dump.
constexpr int kDumpAttempts = 3;

Unexpected<LinkError> system_failure(const std::string& what, int error) {
    return unexpected(
        LinkError{LinkErrc::SystemError, fmt::format("link state monitor: {}: {}", what, std::system_category().message(error))});
}

}  // namespace

Expected<std::unique_ptr<LinkStateMonitor>, LinkError> LinkStateMonitor::open(std::vector<std::string> interfaces) {
    const int socket = ::socket(AF_NETLINK, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, NETLINK_ROUTE);
    if (socket < 0) return system_failure("netlink socket", errno);
    std::unique_ptr<LinkStateMonitor> monitor(
        new LinkStateMonitor(socket, std::set<std::string>(interfaces.begin(), interfaces.end())));

    sockaddr_nl local{};
    local.nl_family = AF_NETLINK;
    local.nl_groups = RTMGRP_LINK;
    if (::bind(socket, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) != 0) {
        return system_failure("subscribing to link notifications", errno);
    }
    // Subscribed first, then dumped: no change can fall between the two.
    std::vector<LinkStateChange> initial;
    if (auto synchronised = monitor->synchronise(initial); !synchronised) return unexpected(synchronised.error());
    return monitor;
}

LinkStateMonitor::LinkStateMonitor(int socket, std::set<std::string> watched)
    : socket_(socket), watched_(std::move(watched)), buffer_(kDatagramCapacity) {}

LinkStateMonitor::~LinkStateMonitor() { ::close(socket_); }

std::vector<LinkStateChange> LinkStateMonitor::read_changes() {
    std::vector<LinkStateChange> changes;
    if (!drain(changes)) {
        logger("link")->warn("link state monitor: notifications were lost; reading all interfaces again");
        if (auto synchronised = synchronise(changes); !synchronised) {
            logger("link")->error("{}", synchronised.error().message);
        }
    }
    return changes;
}

std::optional<bool> LinkStateMonitor::is_up(const std::string& interface) const {
    const auto found = states_.find(interface);
    if (found == states_.end()) return std::nullopt;
    return found->second;
}

Expected<void, LinkError> LinkStateMonitor::synchronise(std::vector<LinkStateChange>& changes) {
    for (int attempt = 0; attempt < kDumpAttempts; ++attempt) {
        const auto request = detail::encode_link_dump_request(++sequence_);
        if (::send(socket_, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
            return system_failure("requesting the interface list", errno);
        }
        States fresh;
        bool complete = true;
        bool done = false;
        const auto deadline = Clock::now() + kDumpTimeout;
        while (!done) {
            std::size_t size = 0;
            const ReadResult result = read_datagram(size);
            if (result == ReadResult::Failed) return system_failure("reading the interface list", errno);
            if (result == ReadResult::NotificationsLost) {
                complete = false;
                continue;
            }
            if (result == ReadResult::NothingWaiting) {
                auto ready = detail::wait_readable(socket_, deadline - Clock::now());
                if (!ready) {
                    return unexpected(LinkError{LinkErrc::SystemError,
                                                "link state monitor: waiting for the interface list: " + ready.error()});
                }
                if (!*ready) {
                    return unexpected(LinkError{LinkErrc::SystemError,
                                                "link state monitor: the kernel did not finish the interface list"});
                }
                continue;
            }
            auto batch = detail::decode_netlink_link_messages(ConstBytes(buffer_).first(size));
            if (!batch) {
                logger("link")->warn("link state monitor: unreadable netlink datagram at byte {}: {}",
                                     batch.error().offset, batch.error().problem);
                complete = false;
                continue;
            }
            if (batch->error != 0) return system_failure("listing interfaces", -batch->error);
            for (const auto& message : batch->links) apply(message, fresh);
            done = batch->dump_done;
        }
        if (complete) {
            report_differences(states_, fresh, changes);
            states_ = std::move(fresh);
            return {};
        }
    }
    return unexpected(LinkError{LinkErrc::SystemError,
                                fmt::format("link state monitor: notifications kept being lost during {} interface dumps",
                                            kDumpAttempts)});
}

bool LinkStateMonitor::drain(std::vector<LinkStateChange>& changes) {
    bool complete = true;
    while (true) {
        std::size_t size = 0;
        switch (read_datagram(size)) {
            case ReadResult::NothingWaiting:
                return complete;
            case ReadResult::NotificationsLost:
                complete = false;
                continue;
            case ReadResult::Failed:
                logger("link")->error("link state monitor: {}", std::system_category().message(errno));
                return complete;
            case ReadResult::Datagram:
                break;
        }
        auto batch = detail::decode_netlink_link_messages(ConstBytes(buffer_).first(size));
        if (!batch) {
            logger("link")->warn("link state monitor: unreadable netlink datagram at byte {}: {}", batch.error().offset,
                                 batch.error().problem);
            complete = false;
            continue;
        }
        States updated = states_;
        for (const auto& message : batch->links) apply(message, updated);
        report_differences(states_, updated, changes);
        states_ = std::move(updated);
    }
}

LinkStateMonitor::ReadResult LinkStateMonitor::read_datagram(std::size_t& size) {
    while (true) {
        sockaddr_nl sender{};
        iovec data{buffer_.data(), buffer_.size()};
        msghdr message{};
        message.msg_name = &sender;
        message.msg_namelen = sizeof(sender);
        message.msg_iov = &data;
        message.msg_iovlen = 1;
        const ssize_t received = ::recvmsg(socket_, &message, MSG_DONTWAIT);
        if (received < 0) {
            if (errno == EINTR) continue;
            if (errno == EAGAIN || errno == EWOULDBLOCK) return ReadResult::NothingWaiting;
            if (errno == ENOBUFS) return ReadResult::NotificationsLost;
            return ReadResult::Failed;
        }
        if (sender.nl_pid != 0) continue;  // not from the kernel
        if ((message.msg_flags & MSG_TRUNC) != 0) return ReadResult::NotificationsLost;
        size = static_cast<std::size_t>(received);
        return ReadResult::Datagram;
    }
}

void LinkStateMonitor::apply(const detail::LinkMessage& message, States& states) const {
    if (message.name.empty()) return;
    if (!watched_.empty() && !watched_.contains(message.name)) return;
    if (message.kind == detail::LinkMessage::Kind::Deleted) {
        states.erase(message.name);
    } else {
        states[message.name] = message.is_up();
    }
}

void LinkStateMonitor::report_differences(const States& before, const States& after,
                                          std::vector<LinkStateChange>& changes) {
    const auto now = Clock::now();
    const auto state_in = [](const States& states, const std::string& name) {
        const auto found = states.find(name);
        return found != states.end() && found->second;
    };
    auto note = [&](const std::string& name) {
        const bool was_up = state_in(before, name);
        const bool is_up = state_in(after, name);
        if (was_up == is_up) return;
        logger("link")->info("interface '{}': link {}", name, is_up ? "up" : "down");
        changes.push_back(LinkStateChange{name, is_up, now});
    };
    for (const auto& [name, up] : after) note(name);
    for (const auto& [name, up] : before) {
        if (!after.contains(name)) note(name);
    }
}

}  // namespace ecpair::link
