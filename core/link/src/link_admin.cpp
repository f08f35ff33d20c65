// One NETLINK_ROUTE socket without multicast subscriptions, so everything it
// reads is an answer to a request it sent. Each request carries a fresh
// sequence number; datagrams with another one (a late answer to a request
// that timed out) are skipped. A set is answered by an NLMSG_ERROR (0 = ack);
// a get by an RTM_NEWLINK with the interface's flags, then the ack.

#include "ecpair/link/link_admin.hpp"

// glibc's <net/if.h> first: <linux/if.h> then leaves out what glibc defines,
// so both may meet in one translation unit (a unity build).
#include <net/if.h>
#include <linux/if.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "netlink_link_messages.hpp"
#include "wait_readable.hpp"

namespace ecpair::link {
namespace {

Unexpected<LinkError> failure(const std::string& ifname, const std::string& what, int error) {
    const LinkErrc code = error == ENODEV     ? LinkErrc::InterfaceNotFound
                          : error == EPERM || error == EACCES ? LinkErrc::PermissionDenied
                                                              : LinkErrc::SystemError;
    return unexpected(LinkError{code, fmt::format("{}: {}: {}", ifname, what, std::system_category().message(error))});
}

}  // namespace

Expected<std::unique_ptr<LinkAdmin>, LinkError> LinkAdmin::open() {
    const int socket = ::socket(AF_NETLINK, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, NETLINK_ROUTE);
    if (socket < 0) return failure("netlink", "opening a route socket", errno);
    sockaddr_nl local{};
    local.nl_family = AF_NETLINK;
    if (::bind(socket, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) != 0) {
        const int error = errno;
        ::close(socket);
        return failure("netlink", "binding a route socket", error);
    }
    return std::unique_ptr<LinkAdmin>(new LinkAdmin(socket));
}

LinkAdmin::~LinkAdmin() { ::close(socket_); }

Expected<void, LinkError> LinkAdmin::set_up(const std::string& ifname, bool up) {
    auto answered = exchange(ifname, false, up);
    if (!answered) return unexpected(answered.error());
    return {};
}

Expected<bool, LinkError> LinkAdmin::is_up(const std::string& ifname) {
    auto answered = exchange(ifname, true, false);
    if (!answered) return unexpected(answered.error());
    if (!answered->has_value()) return failure(ifname, "reading its flags", EPROTO);
    return (**answered & IFF_UP) != 0;
}

Expected<std::optional<unsigned>, LinkError> LinkAdmin::exchange(const std::string& ifname, bool get, bool up) {
    const char* what = get ? "reading its flags" : up ? "setting it up" : "setting it down";
    if (ifname.empty() || ifname.size() >= IFNAMSIZ) return failure(ifname, what, ENODEV);
    const std::uint32_t sequence = ++sequence_;
    const auto request = get ? detail::encode_link_get_request(sequence, ifname)
                             : detail::encode_link_admin_request(sequence, ifname, up);
    sockaddr_nl kernel{};
    kernel.nl_family = AF_NETLINK;
    if (::sendto(socket_, request.data(), request.size(), 0, reinterpret_cast<const sockaddr*>(&kernel),
                 sizeof(kernel)) != static_cast<ssize_t>(request.size())) {
        return failure(ifname, what, errno);
    }
    std::optional<unsigned> flags;
    std::vector<std::uint8_t> buffer(16 * 1024);
    const auto deadline = Clock::now() + kAnswerTimeout;
    for (;;) {
        const ssize_t received = ::recv(socket_, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (received < 0) {
            if (errno == EINTR) continue;
            if (errno != EAGAIN && errno != EWOULDBLOCK) return failure(ifname, what, errno);
            auto ready = detail::wait_readable(socket_, deadline - Clock::now());
            if (!ready) return unexpected(LinkError{LinkErrc::SystemError, ifname + ": " + ready.error()});
            if (!*ready) return failure(ifname, what, ETIMEDOUT);
            continue;
        }
        auto batch = detail::decode_netlink_link_messages(
            ConstBytes(buffer.data(), static_cast<std::size_t>(received)));
        if (!batch) {
            return unexpected(LinkError{LinkErrc::SystemError,
                                        fmt::format("{}: unreadable netlink answer at byte {}: {}", ifname,
                                                    batch.error().offset, batch.error().problem)});
        }
        if (batch->sequence != sequence) continue;  // a late answer to an earlier request
        for (const auto& link : batch->links) {
            if (link.name == ifname) flags = link.flags;
        }
        if (batch->acknowledged) {
            if (batch->error != 0) return failure(ifname, what, -batch->error);
            return flags;
        }
    }
}

}  // namespace ecpair::link
