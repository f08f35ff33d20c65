#include "ecpair/linkguard/guard_logic.hpp"

#include <algorithm>

#include "ecpair/common/log.hpp"
#include "linkguard_log.hpp"

namespace ecpair::linkguard {

std::string_view to_string(GuardState state) {
    switch (state) {
        case GuardState::Idle: return "idle";
        case GuardState::Watching: return "watching";
        case GuardState::LinksDown: return "links-down";
        case GuardState::Finished: return "finished";
    }
    return "unknown";
}

GuardLogic::GuardLogic(GuardOptions options, Io io) : options_(std::move(options)), io_(std::move(io)) {}

void GuardLogic::enter(GuardState next, std::string_view why) {
    if (next == state_) return;
    log()->info("link guard {}: {} -> {} ({})", options_.name, to_string(state_), to_string(next), why);
    state_ = next;
}

std::uint32_t GuardLogic::silence_ms(Clock::time_point now) const {
    if (!last_heartbeat_) return 0;
    return static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(now - *last_heartbeat_).count());
}

std::chrono::nanoseconds GuardLogic::look_interval() const {
    return std::max<std::chrono::nanoseconds>(std::chrono::milliseconds(1), std::chrono::nanoseconds(options_.hang_timeout) / 8);
}

std::optional<GuardLogic::Clock::time_point> GuardLogic::deadline() const {
    if (state_ != GuardState::Watching || !last_heartbeat_) return std::nullopt;
    const auto left = std::chrono::nanoseconds(options_.hang_timeout) - counted_silence_;
    return last_look_ + std::clamp(left, std::chrono::nanoseconds(0), look_interval());
}

void GuardLogic::on_message(const GuardMessage& message, Clock::time_point now) {
    if (finished()) return;
    switch (message.kind) {
        case GuardMessageKind::Heartbeat: heartbeat(message.cycle, now); return;
        case GuardMessageKind::LinksUp: links_up(now); return;
        case GuardMessageKind::Shutdown: take_links_down(DownReason::DaemonStopping, now, true); return;
        default:
            log()->warn("link guard {}: ignoring a {} message (only the guard sends those)", options_.name,
                        to_string(message.kind));
            return;
    }
}

void GuardLogic::heartbeat(std::uint64_t cycle, Clock::time_point now) {
    if (last_heartbeat_ && cycle <= last_cycle_) return;  // the cycle did not advance: no heartbeat
    const std::uint32_t silent = silence_ms(now);
    last_heartbeat_ = now;
    last_look_ = now;
    counted_silence_ = std::chrono::nanoseconds(0);
    last_cycle_ = cycle;
    if (state_ == GuardState::Idle) {
        enter(GuardState::Watching, "first heartbeat");
    } else if (state_ == GuardState::LinksDown && !resumed_reported_) {
        resumed_reported_ = true;
        log()->warn("link guard {}: the cycle advances again (cycle {}) after {} ms without a heartbeat; "
                    "{} stay down until ecpaird asks for them",
                    options_.name, cycle, silent, options_.links);
        GuardMessage report;
        report.kind = GuardMessageKind::HeartbeatResumed;
        report.silence_ms = silent;
        report.cycle = cycle;
        io_.report(report);
    }
}

void GuardLogic::links_up(Clock::time_point now) {
    const LinkResult result = io_.set_links(true);
    GuardMessage report;
    report.kind = GuardMessageKind::LinksAreUp;
    report.links = result.links;
    report.error = result.error;
    report.cycle = last_cycle_;
    if (state_ == GuardState::LinksDown && down_at_) {
        report.silence_ms =
            static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(now - *down_at_).count());
    }
    if (result.error != 0) {
        log()->error("link guard {}: bringing {} up failed: {}", options_.name, options_.links, result.message);
    } else {
        log()->info("link guard {}: {} up (asked by ecpaird)", options_.name, options_.links);
    }
    io_.report(report);
    if (state_ == GuardState::LinksDown) {
        resumed_reported_ = false;
        // Watching again from the last heartbeat: if the cycle is still stuck the links go down at once.
        if (last_heartbeat_) {
            enter(GuardState::Watching, "ecpaird brought the links back");
            on_time(now);
        } else {
            enter(GuardState::Idle, "ecpaird brought the links back");
        }
    }
}

void GuardLogic::on_time(Clock::time_point now) {
    if (state_ != GuardState::Watching || !last_heartbeat_ || now <= last_look_) return;
    const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(now - last_look_);
    const auto counted = std::min(elapsed, 2 * look_interval());
    if (counted < elapsed) {
        log()->info("link guard {}: its own look came {:.1f} ms late (the machine stalled); {:.1f} ms of that counted",
                    options_.name, std::chrono::duration<double, std::milli>(elapsed - look_interval()).count(),
                    std::chrono::duration<double, std::milli>(counted).count());
    }
    counted_silence_ += counted;
    last_look_ = now;
    if (counted_silence_ >= options_.hang_timeout) take_links_down(DownReason::HeartbeatStopped, now, true);
}

void GuardLogic::on_daemon_gone(Clock::time_point now) {
    if (finished()) return;
    take_links_down(DownReason::DaemonGone, now, false);
}

void GuardLogic::take_links_down(DownReason reason, Clock::time_point now, bool report) {
    const std::uint32_t silent = silence_ms(now);
    // Already down because of a hang: setting them down again costs nothing and
    // covers someone having brought them up behind the guard's back.
    const LinkResult result = io_.set_links(false);
    if (result.error != 0) {
        log()->error("link guard {}: taking {} down failed: {} (reason: {})", options_.name, options_.links,
                     result.message, describe(reason));
    } else if (last_heartbeat_) {
        log()->warn("link guard {}: {} down: {}; {} ms after the last heartbeat (cycle {})", options_.name,
                    options_.links, describe(reason), silent, last_cycle_);
    } else {
        log()->warn("link guard {}: {} down: {}; no heartbeat had come yet", options_.name, options_.links,
                    describe(reason));
    }
    if (report) {
        GuardMessage message;
        message.kind = GuardMessageKind::LinksTakenDown;
        message.reason = reason;
        message.links = result.links;
        message.error = result.error;
        message.silence_ms = silent;
        message.cycle = last_cycle_;
        io_.report(message);
    }
    if (reason == DownReason::HeartbeatStopped) {
        resumed_reported_ = false;
        down_at_ = now;
        enter(GuardState::LinksDown, describe(reason));
    } else {
        enter(GuardState::Finished, describe(reason));
    }
}

}  // namespace ecpair::linkguard
