// The operations side of ecpaird's composition: the link guard it starts
// before opening the links, and the line systemd shows for it.

#include <fmt/format.h>

#include "daemon.hpp"
#include "ecpair/common/log.hpp"

namespace ecpair::daemon {

int Daemon::open_link_guard() {
    if (!settings_.link_guard.enabled) return kOk;
    linkguard::LinkGuardOptions options;
    options.name = settings_.name;
    options.main_interface = settings_.main_interface;
    options.red_interface = settings_.red_interface;
    // The heartbeat needs the cycle to advance between two looks: at slow
    // cycles the timeout grows to four cycles.
    const auto four_cycles = std::chrono::duration_cast<std::chrono::milliseconds>(4 * cycle_time());
    options.hang_timeout = std::max(settings_.link_guard.hang_timeout, four_cycles);
    if (options.hang_timeout != settings_.link_guard.hang_timeout) {
        logger("ecpaird")->warn("link_guard.hang_timeout_ms {} is under four cycles of {} µs: using {} ms",
                                settings_.link_guard.hang_timeout.count(), cycle_time().count(),
                                options.hang_timeout.count());
    }
    // Below the receive threads (priority - 1), above everything else.
    options.realtime_priority = std::max(settings_.realtime_priority - 2, 0);
    options.log_level = settings_.log_level;
    auto started = linkguard::LinkGuard::start(io_, options, [this] { return master_ ? master_->cycle() : 0; }, events_);
    if (!started) {
        logger("ecpaird")->error("{}", started.error());
        return kLinkFailure;
    }
    link_guard_ = std::move(*started);
    return kOk;
}

std::unique_ptr<LinkGuardResumePolicy> Daemon::make_link_guard_policy() {
    std::optional<PairRole> pair;
    if (redundancy_ && supervisor_) {
        pair = PairRole{[this] { return redundancy_->state() == redundancy::RedState::Active; },
                        [this] { supervisor_->request_role(redundancy::RedState::Inactive); }};
    }
    return std::make_unique<LinkGuardResumePolicy>(io_, *link_guard_, *master_, std::move(pair));
}

std::string Daemon::service_status() const {
    std::string role = redundancy_ ? fmt::format("{}, ", redundancy::to_string(redundancy_->state())) : std::string();
    if (link_guard_ && link_guard_->links_down()) role += "links down by the link guard, ";
    return fmt::format("{}master {}", role, eni::to_string(master_->state()));
}

}  // namespace ecpair::daemon
