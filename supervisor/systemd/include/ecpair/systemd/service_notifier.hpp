#pragma once
// ecpaird as a systemd Type=notify service (sd_notify(3)):
//   READY=1     once the daemon runs (links open, threads started, socket listening)
//   WATCHDOG=1  every WatchdogSec / 3, but only when the cycle counter advanced
//               since the last look: a daemon whose cycle hangs is restarted
//               by systemd even while its control thread still answers
//   STATUS=...  one line for `systemctl status` (role, master state), when it changes
//   STOPPING=1  when the shutdown begins
// Outside systemd ($NOTIFY_SOCKET unset) nothing is sent.
//
// Runs on the control thread's io_context.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

namespace ecpair::systemd {

class ServiceNotifier {
public:
    using Send = std::function<void(const std::string& state)>;
    using CycleCounter = std::function<std::uint64_t()>;
    using StatusText = std::function<std::string()>;

    // sd_notify() and the watchdog interval systemd gave this process (none: no pings).
    static std::unique_ptr<ServiceNotifier> from_environment(boost::asio::io_context& io, CycleCounter cycle,
                                                             StatusText status);

    ServiceNotifier(boost::asio::io_context& io, std::optional<std::chrono::microseconds> watchdog, Send send,
                    CycleCounter cycle, StatusText status);

    void ready();
    void stopping();
    // One look at the cycle: WATCHDOG=1 when it advanced (the timer calls this).
    void watch();

    std::optional<std::chrono::microseconds> watchdog_interval() const { return watchdog_; }
    std::uint64_t watchdog_pings() const { return pings_; }
    std::uint64_t watchdog_withheld() const { return withheld_; }

private:
    void arm();

    std::optional<std::chrono::microseconds> watchdog_;
    Send send_;
    CycleCounter cycle_;
    StatusText status_;
    boost::asio::steady_timer timer_;
    std::uint64_t last_cycle_ = 0;
    std::string last_status_;
    std::uint64_t pings_ = 0;
    std::uint64_t withheld_ = 0;
    bool standing_still_ = false;
    bool stopping_ = false;
};

}  // namespace ecpair::systemd
