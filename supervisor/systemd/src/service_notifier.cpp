#include "ecpair/systemd/service_notifier.hpp"

#include <systemd/sd-daemon.h>

#include "ecpair/common/log.hpp"

namespace ecpair::systemd {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("systemd"); }

}  // namespace

std::unique_ptr<ServiceNotifier> ServiceNotifier::from_environment(boost::asio::io_context& io, CycleCounter cycle,
                                                                   StatusText status) {
    std::optional<std::chrono::microseconds> watchdog;
    std::uint64_t usec = 0;
    // > 0 only when WATCHDOG_USEC is set for this process (WATCHDOG_PID, if set, is ours).
    if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) watchdog = std::chrono::microseconds(usec);
    return std::make_unique<ServiceNotifier>(
        io, watchdog, [](const std::string& state) { (void)sd_notify(0, state.c_str()); }, std::move(cycle),
        std::move(status));
}

ServiceNotifier::ServiceNotifier(boost::asio::io_context& io, std::optional<std::chrono::microseconds> watchdog,
                                 Send send, CycleCounter cycle, StatusText status)
    : watchdog_(watchdog), send_(std::move(send)), cycle_(std::move(cycle)), status_(std::move(status)), timer_(io) {}

void ServiceNotifier::ready() {
    last_cycle_ = cycle_();
    last_status_ = status_();
    send_("READY=1\nSTATUS=" + last_status_);
    if (watchdog_) {
        log()->info("systemd watchdog every {} ms, pinged while the cycle advances",
                    std::chrono::duration_cast<std::chrono::milliseconds>(*watchdog_).count());
        arm();
    }
}

void ServiceNotifier::stopping() {
    stopping_ = true;
    timer_.cancel();
    send_("STOPPING=1\nSTATUS=stopping");
}

void ServiceNotifier::arm() {
    timer_.expires_after(*watchdog_ / 3);
    timer_.async_wait([this](const boost::system::error_code& ec) {
        if (ec || stopping_) return;
        watch();
        arm();
    });
}

void ServiceNotifier::watch() {
    if (stopping_) return;
    const std::uint64_t cycle = cycle_();
    std::string state;
    if (cycle != last_cycle_) {
        state = "WATCHDOG=1";
        ++pings_;
        if (standing_still_) log()->info("the cycle advances again (cycle {}): watchdog pings resume", cycle);
        standing_still_ = false;
    } else {
        ++withheld_;
        if (!standing_still_) log()->warn("the cycle stands still at {}: no systemd watchdog ping", cycle);
        standing_still_ = true;
    }
    last_cycle_ = cycle;
    if (auto text = status_(); text != last_status_) {
        last_status_ = text;
        state += (state.empty() ? "" : "\n") + std::string("STATUS=") + text;
    }
    if (!state.empty()) send_(state);
}

}  // namespace ecpair::systemd
