// The guard runs in a process group of its own (a Ctrl-C or a signal to
// ecpaird's group does not reach it) and gets its end of the socket pair as
// fd 3; every other descriptor of ecpaird is close-on-exec, so only this
// process holds the other end and its death is the guard's end-of-file.

#include "ecpair/linkguard/link_guard.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/common/realtime.hpp"
#include "ecpair/linkguard/link_guard_events.hpp"
#include "linkguard_log.hpp"

extern char** environ;

namespace ecpair::linkguard {
namespace {

constexpr int kGuardFd = 3;
constexpr rlim_t kHighestGuardFd = 65535;
constexpr std::chrono::seconds kStartPatience{5};
constexpr std::chrono::seconds kStopPatience{2};

std::string errno_text(int error) { return std::strerror(error); }

// When a process is killed the kernel closes its descriptors in ascending
// order but releases the files in reverse (the exiting task's work list is
// last in, first out). Closing a packet socket (each PcapLink) waits for an
// RCU grace period, tens of milliseconds for the two links: the guard's
// socket, released first from the top of the table, reports the death at
// once instead of after them. So it lives at the highest descriptor allowed.
int move_to_top(int fd) {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur < 64) return fd;
    const auto top = static_cast<int>(std::min<rlim_t>(limit.rlim_cur - 1, kHighestGuardFd));
    const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, top);
    if (moved < 0) return fd;
    ::close(fd);
    return moved;
}

// Waits up to `patience` for one message; nullopt on timeout or end-of-file.
std::optional<GuardMessage> receive_blocking(int socket, std::chrono::milliseconds patience) {
    const auto deadline = std::chrono::steady_clock::now() + patience;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) return std::nullopt;
        pollfd entry{socket, POLLIN, 0};
        const int ready = ::poll(&entry, 1, static_cast<int>(left.count()));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) return std::nullopt;
        std::array<std::uint8_t, 64> buffer{};
        const ssize_t n = ::recv(socket, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) return std::nullopt;
        auto message = decode(ConstBytes(buffer.data(), static_cast<std::size_t>(n)));
        if (message) return *message;
        log()->warn("link guard: malformed message from the guard (byte {}: {})", message.error().offset,
                    message.error().problem);
    }
}

}  // namespace

std::string LinkGuard::default_binary() {
    std::error_code error;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) return "ecpair-linkguard";
    return (self.parent_path() / "ecpair-linkguard").string();
}

Expected<std::unique_ptr<LinkGuard>, std::string> LinkGuard::start(boost::asio::io_context& io, LinkGuardOptions options,
                                                                   CycleCounter cycle, master::EventQueue& events) {
    if (options.binary.empty()) options.binary = default_binary();
    int pair[2];
    if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, pair) != 0) {
        return unexpected(fmt::format("link guard: socketpair: {}", errno_text(errno)));
    }
    const int ours = move_to_top(pair[0]);
    int theirs = pair[1];
    // dup2(fd, 3) would keep close-on-exec if theirs were 3 already: move it out of the way.
    if (theirs == kGuardFd) {
        theirs = ::fcntl(pair[1], F_DUPFD_CLOEXEC, kGuardFd + 1);
        ::close(pair[1]);
    }

    const std::string fd_text = std::to_string(kGuardFd);
    const std::string timeout_text = std::to_string(options.hang_timeout.count());
    const std::string priority_text = std::to_string(options.realtime_priority);
    std::vector<std::string> arguments{options.binary, "--fd", fd_text, "--name", options.name, "--main",
                                       options.main_interface, "--hang-timeout-ms", timeout_text,
                                       "--realtime-priority", priority_text, "--log-level", options.log_level};
    if (!options.red_interface.empty()) {
        arguments.push_back("--red");
        arguments.push_back(options.red_interface);
    }
    std::vector<char*> argv;
    for (auto& a : arguments) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, theirs, kGuardFd);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none;
    sigemptyset(&none);
    sigset_t defaults;
    sigemptyset(&defaults);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGCHLD}) sigaddset(&defaults, s);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    pid_t pid = -1;
    const int spawned = ::posix_spawn(&pid, options.binary.c_str(), &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(theirs);
    if (spawned != 0) {
        ::close(ours);
        return unexpected(fmt::format("link guard: cannot start {}: {}", options.binary, errno_text(spawned)));
    }
    std::unique_ptr<LinkGuard> guard(new LinkGuard(io, std::move(options), std::move(cycle), events, ours, pid));
    if (auto up = guard->bring_links_up_at_start(); !up) return unexpected(up.error());
    guard->watch_reports();
    return guard;
}

LinkGuard::LinkGuard(boost::asio::io_context& io, LinkGuardOptions options, CycleCounter cycle,
                     master::EventQueue& events, int socket, pid_t pid)
    : io_(io), options_(std::move(options)), cycle_(std::move(cycle)), events_(events), socket_(socket), pid_(pid) {}

LinkGuard::~LinkGuard() { shutdown(); }

Expected<void, std::string> LinkGuard::bring_links_up_at_start() {
    GuardMessage up;
    up.kind = GuardMessageKind::LinksUp;
    if (!send(up)) return unexpected(fmt::format("link guard: cannot talk to {}: {}", options_.binary, errno_text(errno)));
    for (;;) {
        const auto answer = receive_blocking(socket_, kStartPatience);
        if (!answer) {
            const int status = reap(std::chrono::milliseconds(500));
            return unexpected(fmt::format("link guard: {} did not bring the links up within {} s{}", options_.binary,
                                          kStartPatience.count(),
                                          status >= 0 ? fmt::format(" (it exited with status {})", status) : ""));
        }
        if (answer->kind != GuardMessageKind::LinksAreUp) continue;
        if (answer->error != 0) {
            return unexpected(fmt::format("link guard: bringing {} up failed: {} (the guard needs CAP_NET_ADMIN; "
                                          "link_guard.enabled: false turns it off)",
                                          links_text(static_cast<std::uint8_t>((kMainLink | kRedLink) & ~answer->links)),
                                          errno_text(answer->error)));
        }
        ++links_brought_up_;
        raise(events::kLinkGuardLinksUp, 0, answer->links, 0, 0);
        log()->info("link guard {}: running (pid {}), links up, down after {} ms without a heartbeat or when ecpaird ends",
                    options_.name, pid_, options_.hang_timeout.count());
        return {};
    }
}

bool LinkGuard::send(const GuardMessage& message) {
    const auto bytes = encode(message);
    return ::send(socket_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
}

void LinkGuard::watch_reports() {
    // Asio waits on the socket itself (a second descriptor would keep it open at exit).
    if (!reports_) reports_.emplace(io_, socket_);
    reports_->async_wait(boost::asio::posix::stream_descriptor::wait_read, [this](const boost::system::error_code& ec) {
        if (ec || stopped_) return;
        for (;;) {
            std::array<std::uint8_t, 64> buffer{};
            const ssize_t n = ::recv(socket_, buffer.data(), buffer.size(), MSG_DONTWAIT);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && errno == EAGAIN) break;
            if (n <= 0) {
                guard_gone();
                return;
            }
            auto report = decode(ConstBytes(buffer.data(), static_cast<std::size_t>(n)));
            if (!report) {
                log()->warn("link guard: malformed message from the guard (byte {}: {})", report.error().offset,
                            report.error().problem);
                continue;
            }
            handle(*report);
        }
        watch_reports();
    });
}

void LinkGuard::handle(const GuardMessage& report) {
    switch (report.kind) {
        case GuardMessageKind::LinksTakenDown: {
            LinksDownReport down{report.reason, report.links, std::chrono::milliseconds(report.silence_ms), report.cycle,
                                 report.error};
            links_down_ = true;
            ++links_taken_down_;
            last_down_ = down;
            raise(events::kLinkGuardLinksDown, static_cast<std::uint32_t>(report.reason), report.links,
                  report.silence_ms, static_cast<std::uint32_t>(report.error));
            log()->warn("link guard {}: the guard took {} down ({} ms without a heartbeat, last cycle {}); they stay "
                        "down until this master may drive them",
                        options_.name, links_text(report.links), report.silence_ms, report.cycle);
            if (on_links_down_) on_links_down_(down);
            return;
        }
        case GuardMessageKind::HeartbeatResumed:
            raise(events::kLinkGuardResumed, 0, 0, report.silence_ms, 0);
            return;
        case GuardMessageKind::LinksAreUp:
            links_down_ = report.error != 0 && links_down_;
            ++links_brought_up_;
            raise(events::kLinkGuardLinksUp, 1, report.links, report.silence_ms,
                  static_cast<std::uint32_t>(report.error));
            log()->info("link guard {}: {} up again after {} ms down{}", options_.name, links_text(report.links),
                        report.silence_ms,
                        report.error != 0 ? fmt::format("; failed for some: {}", errno_text(report.error)) : "");
            return;
        default:
            log()->warn("link guard: unexpected {} message from the guard", to_string(report.kind));
            return;
    }
}

void LinkGuard::bring_links_up() {
    if (stopped_ || !running_) return;
    GuardMessage up;
    up.kind = GuardMessageKind::LinksUp;
    if (!send(up)) log()->error("link guard {}: cannot ask the guard for the links: {}", options_.name, errno_text(errno));
}

void LinkGuard::guard_gone() {
    running_ = false;
    const int status = reap(std::chrono::milliseconds(500));
    raise(events::kLinkGuardGone, static_cast<std::uint32_t>(status), 0, 0, 0);
    log()->error("link guard {}: the guard process ended (status {}): MAIN and RED are no longer guarded", options_.name,
                 status);
}

void LinkGuard::start_heartbeat() {
    if (heartbeat_.joinable() || stopped_) return;
    heartbeat_ = std::thread([this] { heartbeat_loop(); });
}

// Sleeps hang_timeout / 4 between looks at the cycle counter: a heartbeat
// late by up to three quarters of the timeout still arrives in time.
void LinkGuard::heartbeat_loop() {
    request_realtime(options_.realtime_priority, "link guard heartbeat");
    const auto period = std::max<std::chrono::microseconds>(options_.hang_timeout / 4, std::chrono::milliseconds(1));
    std::uint64_t last_cycle = cycle_();
    auto last_sent = std::chrono::steady_clock::now();
    bool sent_any = false;
    auto next = std::chrono::steady_clock::now();
    std::unique_lock lock(heartbeat_mutex_);
    while (!heartbeat_stop_) {
        next += period;
        heartbeat_wake_.wait_until(lock, next, [this] { return heartbeat_stop_; });
        if (heartbeat_stop_) return;
        const std::uint64_t cycle = cycle_();
        if (cycle == last_cycle) continue;  // the cycle stands still: no heartbeat
        last_cycle = cycle;
        GuardMessage beat;
        beat.kind = GuardMessageKind::Heartbeat;
        beat.cycle = cycle;
        const auto now = std::chrono::steady_clock::now();
        if (!send(beat)) continue;  // a full socket (the guard is slow): the next one tries again
        if (sent_any) {
            const auto gap = std::chrono::duration_cast<std::chrono::microseconds>(now - last_sent).count();
            if (gap > max_heartbeat_gap_us_.load()) max_heartbeat_gap_us_.store(gap);
        }
        sent_any = true;
        last_sent = now;
        if (next < now) next = now;  // after a stop (SIGSTOP): no burst of catch-up beats
    }
}

void LinkGuard::stop_heartbeat() {
    {
        std::lock_guard lock(heartbeat_mutex_);
        heartbeat_stop_ = true;
    }
    heartbeat_wake_.notify_all();
    if (heartbeat_.joinable()) heartbeat_.join();
}

void LinkGuard::shutdown() {
    if (stopped_) return;
    stopped_ = true;
    stop_heartbeat();
    if (reports_) {
        boost::system::error_code ignored;
        reports_->cancel(ignored);
        (void)reports_->release();  // the descriptor stays ours, closed below
        reports_.reset();
    }
    if (running_) {
        GuardMessage stop;
        stop.kind = GuardMessageKind::Shutdown;
        bool confirmed = false;
        if (send(stop)) {
            const auto deadline = std::chrono::steady_clock::now() + kStopPatience;
            while (!confirmed && std::chrono::steady_clock::now() < deadline) {
                const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
                const auto answer = receive_blocking(socket_, left);
                if (!answer) break;
                confirmed = answer->kind == GuardMessageKind::LinksTakenDown &&
                            answer->reason == DownReason::DaemonStopping;
                if (confirmed) {
                    log()->info("link guard {}: {} down (ecpaird stopping){}", options_.name, links_text(answer->links),
                                answer->error != 0 ? fmt::format("; failed for some: {}", errno_text(answer->error)) : "");
                }
            }
        }
        if (!confirmed) log()->warn("link guard {}: the guard did not confirm the links down; closing its socket", options_.name);
    }
    ::close(socket_);  // end-of-file for the guard in any case
    socket_ = -1;
    const int status = reap(kStopPatience);
    if (status < 0 && pid_ > 0) {
        log()->error("link guard {}: the guard (pid {}) did not exit; killing it", options_.name, pid_);
        ::kill(pid_, SIGKILL);
        reap(kStopPatience);
    }
    running_ = false;
}

// The guard's exit status (128 + signal when a signal ended it), or -1 while it runs after `patience`.
int LinkGuard::reap(std::chrono::milliseconds patience) {
    if (pid_ <= 0) return -1;
    const auto deadline = std::chrono::steady_clock::now() + patience;
    for (;;) {
        int status = 0;
        const pid_t done = ::waitpid(pid_, &status, WNOHANG);
        if (done == pid_ || (done < 0 && errno == ECHILD)) {
            pid_ = -1;
            if (done < 0) return 0;
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        if (std::chrono::steady_clock::now() >= deadline) return -1;
        // A short, bounded wait for a process that is already on its way out.
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

void LinkGuard::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    master::Event event;
    event.kind = kind;
    event.cycle = cycle_();
    event.time = std::chrono::system_clock::now();
    event.a = a;
    event.b = b;
    event.c = c;
    event.d = d;
    events_.push(event);
}

LinkGuardStatus LinkGuard::status() const {
    LinkGuardStatus s;
    s.running = running_;
    s.links_down = links_down_;
    s.hang_timeout = options_.hang_timeout;
    s.links_taken_down = links_taken_down_;
    s.links_brought_up = links_brought_up_;
    s.max_heartbeat_gap = std::chrono::microseconds(max_heartbeat_gap_us_.load());
    s.last_down = last_down_;
    return s;
}

}  // namespace ecpair::linkguard
