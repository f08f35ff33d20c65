#pragma once
// The link guard's decisions (acontis REQ012: the links of a failing master
// must go down), apart from its I/O so that every path runs in virtual time.
// The guard program feeds it the messages from ecpaird, end-of-file on the
// socket, and the passing of time; it calls back to set the links and to
// report to ecpaird.
//
//   Idle      started; the links as ecpaird left them; no heartbeat yet, so a
//             slow start-up is no hang
//   Watching  heartbeats arrive; none for hang_timeout -> links down (LinksDown)
//   LinksDown the guard took the links down because the cycle stopped. They
//             stay down when heartbeats resume (ecpaird may still believe it is
//             ACTIVE); only a LinksUp from ecpaird brings them up (Watching).
//   Finished  ecpaird is gone or stopping: links down, the guard exits
//
// A heartbeat counts only when its cycle is higher than the last one: the
// guard checks for itself that the cycle advances.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "ecpair/linkguard/guard_protocol.hpp"

namespace ecpair::linkguard {

enum class GuardState : std::uint8_t { Idle, Watching, LinksDown, Finished };
std::string_view to_string(GuardState state);

struct LinkResult {
    std::uint8_t links = 0;  // the links now in the wanted state (kMainLink | kRedLink)
    int error = 0;           // errno of the first link that failed (0: all fine)
    std::string message;     // that failure, naming the interface
};

struct GuardOptions {
    std::string name = "ecpaird";  // the daemon instance, for log lines
    std::string links;             // "MAIN m1-main, RED m1-red", for log lines
    std::chrono::milliseconds hang_timeout{500};
};

class GuardLogic {
public:
    using Clock = std::chrono::steady_clock;
    struct Io {
        std::function<LinkResult(bool up)> set_links;
        std::function<void(const GuardMessage&)> report;
    };

    GuardLogic(GuardOptions options, Io io);

    void on_message(const GuardMessage& message, Clock::time_point now);
    void on_daemon_gone(Clock::time_point now);  // end-of-file on the socket
    // Call when deadline() has passed (or at any time: nothing happens before it).
    void on_time(Clock::time_point now);

    // When on_time must be called next; nullopt: nothing to wait for.
    std::optional<Clock::time_point> deadline() const;
    GuardState state() const { return state_; }
    bool finished() const { return state_ == GuardState::Finished; }

private:
    void heartbeat(std::uint64_t cycle, Clock::time_point now);
    void links_up(Clock::time_point now);
    void take_links_down(DownReason reason, Clock::time_point now, bool report);
    std::uint32_t silence_ms(Clock::time_point now) const;
    void enter(GuardState next, std::string_view why);

    GuardOptions options_;
    Io io_;
    GuardState state_ = GuardState::Idle;
    std::optional<Clock::time_point> last_heartbeat_;
    std::optional<Clock::time_point> down_at_;  // when the guard took the links down for a hang
    std::uint64_t last_cycle_ = 0;
    bool resumed_reported_ = false;
};

}  // namespace ecpair::linkguard
