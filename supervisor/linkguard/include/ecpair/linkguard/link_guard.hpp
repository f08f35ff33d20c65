#pragma once
// ecpaird's side of the link guard (acontis REQ012: links at a failing
// master must go down). start() launches ecpair-linkguard as a process of
// its own, tied to this one by a socket pair, and has it bring MAIN and RED
// up. From then on:
//
//  - a heartbeat thread (SCHED_FIFO just below the receive threads) sends
//    the cycle counter every hang_timeout / 4, and only when it advanced: the
//    cycle thread itself makes no system call for it. When the cycle stands
//    still for hang_timeout (a hang, SIGSTOP) the guard takes the links down.
//  - when this process dies (kill -9 included) the kernel closes its end of
//    the socket and the guard takes the links down at once.
//  - shutdown() has the guard take them down and exit.
//
// After a hang the links stay down even when the cycle advances again: this
// master may still believe it is ACTIVE. Whoever decides (the Supervisor;
// until it exists, ecpaird's LinkGuardResumePolicy) learns it through
// on_links_down(), makes the master INACTIVE, then calls bring_links_up().
//
// Threads: start(), the callbacks, bring_links_up(), status() and shutdown()
// on the control thread (the io_context's), start_heartbeat() anywhere.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

#include "ecpair/common/expected.hpp"
#include "ecpair/linkguard/guard_protocol.hpp"
#include "ecpair/master/event_queue.hpp"

namespace ecpair::linkguard {

struct LinkGuardOptions {
    std::string name = "ecpaird";  // the instance, for log lines
    std::string main_interface;
    std::string red_interface;  // empty: no RED adapter
    std::chrono::milliseconds hang_timeout{50};
    std::string binary;         // the guard program; empty: ecpair-linkguard next to this program
    int realtime_priority = 0;  // the guard process and the heartbeat thread (0: none)
    std::string log_level = "info";
};

struct LinksDownReport {
    DownReason reason = DownReason::None;
    std::uint8_t links = 0;  // the links the guard did take down
    std::chrono::milliseconds silence{0};  // without a heartbeat when it acted
    std::uint64_t last_cycle = 0;          // of the last heartbeat
    int error = 0;                         // errno of a link it could not take down
};

struct LinkGuardStatus {
    bool running = false;     // the guard process is there
    bool links_down = false;  // the guard took the links down and they have not been brought back
    std::chrono::milliseconds hang_timeout{0};
    std::uint64_t links_taken_down = 0;  // times the guard took them down
    std::uint64_t links_brought_up = 0;  // times they were brought up (the start included)
    std::chrono::microseconds max_heartbeat_gap{0};  // the longest time between two heartbeats sent
    std::optional<LinksDownReport> last_down;
};

class LinkGuard {
public:
    using CycleCounter = std::function<std::uint64_t()>;

    // Launches the guard and waits (a few seconds at most) until it has set
    // the links up. The error names what failed (the program, a link, a permission).
    static Expected<std::unique_ptr<LinkGuard>, std::string> start(boost::asio::io_context& io, LinkGuardOptions options,
                                                                   CycleCounter cycle, master::EventQueue& events);
    ~LinkGuard();
    LinkGuard(const LinkGuard&) = delete;
    LinkGuard& operator=(const LinkGuard&) = delete;

    // Starts the heartbeat thread; call once the cycle runs.
    void start_heartbeat();

    // The guard took the links down because the cycle stood still. Called on
    // the control thread when this process hears of it (after a SIGSTOP: once it runs again).
    void set_on_links_down(std::function<void(const LinksDownReport&)> callback) { on_links_down_ = std::move(callback); }
    // The guard took the links down and they stay down until bring_links_up().
    bool links_down() const { return links_down_; }
    // Asks the guard to bring the links up again (answered asynchronously:
    // a link-guard-links-up event, links_down() false).
    void bring_links_up();

    // Links down, the guard exits (waits for it a few seconds at most). Idempotent.
    void shutdown();

    LinkGuardStatus status() const;

    // ecpair-linkguard in the directory of the running program.
    static std::string default_binary();

private:
    LinkGuard(boost::asio::io_context& io, LinkGuardOptions options, CycleCounter cycle, master::EventQueue& events,
              int socket, pid_t pid);

    Expected<void, std::string> bring_links_up_at_start();
    bool send(const GuardMessage& message);
    void watch_reports();
    void handle(const GuardMessage& report);
    void guard_gone();
    void heartbeat_loop();
    void stop_heartbeat();
    void raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);
    int reap(std::chrono::milliseconds patience);

    boost::asio::io_context& io_;
    LinkGuardOptions options_;
    CycleCounter cycle_;
    master::EventQueue& events_;
    int socket_ = -1;
    pid_t pid_ = -1;
    std::optional<boost::asio::posix::stream_descriptor> reports_;

    std::function<void(const LinksDownReport&)> on_links_down_;
    bool running_ = true;
    bool links_down_ = false;
    bool stopped_ = false;
    std::uint64_t links_taken_down_ = 0;
    std::uint64_t links_brought_up_ = 0;
    std::optional<LinksDownReport> last_down_;

    std::thread heartbeat_;
    std::mutex heartbeat_mutex_;
    std::condition_variable heartbeat_wake_;
    bool heartbeat_stop_ = false;
    std::atomic<std::int64_t> max_heartbeat_gap_us_{0};
};

}  // namespace ecpair::linkguard
