#include "guard_runner.hpp"

#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "ecpair/common/log.hpp"

namespace ecpair::linkguard {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("linkguard"); }

}  // namespace

std::string GuardInterfaces::describe() const {
    return red.empty() ? "MAIN " + main : "MAIN " + main + ", RED " + red;
}

LinkResult set_links(link::LinkAdmin& admin, const GuardInterfaces& interfaces, bool up) {
    LinkResult result;
    auto one = [&](const std::string& ifname, std::uint8_t bit) {
        if (ifname.empty()) return;
        if (auto set = admin.set_up(ifname, up); set) {
            result.links |= bit;
        } else if (result.error == 0) {
            result.error = set.error().code == link::LinkErrc::InterfaceNotFound  ? ENODEV
                           : set.error().code == link::LinkErrc::PermissionDenied ? EPERM
                                                                                   : EIO;
            result.message = set.error().message;
        }
    };
    // Both are tried even when the first fails: one link down is better than none.
    one(interfaces.main, kMainLink);
    one(interfaces.red, kRedLink);
    return result;
}

GuardRunner::GuardRunner(int socket, GuardInterfaces interfaces, GuardOptions options,
                         std::unique_ptr<link::LinkAdmin> admin)
    : socket_(socket),
      interfaces_(std::move(interfaces)),
      admin_(std::move(admin)),
      logic_(std::move(options), GuardLogic::Io{[this](bool up) { return set_links(*admin_, interfaces_, up); },
                                                [this](const GuardMessage& m) { report(m); }}) {}

void GuardRunner::report(const GuardMessage& message) {
    const auto bytes = encode(message);
    // ecpaird may be stopped (SIGSTOP): never wait for it; a full socket drops the report.
    if (::send(socket_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL) < 0 && errno != EPIPE) {
        log()->warn("link guard: could not tell ecpaird ({}): {}", to_string(message.kind), std::strerror(errno));
    }
}

int GuardRunner::run() {
    std::array<std::uint8_t, 256> buffer{};
    while (!logic_.finished()) {
        int timeout_ms = -1;
        if (const auto due = logic_.deadline()) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(*due - GuardLogic::Clock::now());
            timeout_ms = static_cast<int>(std::max<std::int64_t>(0, left.count() + 1));
        }
        pollfd entry{socket_, POLLIN, 0};
        const int ready = ::poll(&entry, 1, timeout_ms);
        const auto now = GuardLogic::Clock::now();
        if (ready < 0) {
            if (errno == EINTR) continue;
            log()->error("link guard: poll: {}", std::strerror(errno));
            logic_.on_daemon_gone(now);
            break;
        }
        if (ready == 0) {
            logic_.on_time(now);
            continue;
        }
        const ssize_t n = ::recv(socket_, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) {  // end-of-file (or the socket broke): ecpaird is gone
            logic_.on_daemon_gone(now);
            break;
        }
        auto message = decode(ConstBytes(buffer.data(), static_cast<std::size_t>(n)));
        if (!message) {
            log()->warn("link guard: ignoring a malformed message from ecpaird (byte {}: {})", message.error().offset,
                        message.error().problem);
            continue;
        }
        logic_.on_message(*message, now);
        logic_.on_time(now);
    }
    return 0;
}

}  // namespace ecpair::linkguard
