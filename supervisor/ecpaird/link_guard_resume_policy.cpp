#include "link_guard_resume_policy.hpp"

#include "ecpair/common/log.hpp"

namespace ecpair::daemon {

LinkGuardResumePolicy::LinkGuardResumePolicy(boost::asio::io_context& io, linkguard::LinkGuard& guard,
                                             const master::Master& master, std::optional<PairRole> pair)
    : guard_(guard), master_(master), pair_(std::move(pair)), timer_(io) {
    guard_.set_on_links_down([this](const linkguard::LinksDownReport& report) { on_links_down(report); });
}

void LinkGuardResumePolicy::on_links_down(const linkguard::LinksDownReport& report) {
    cycle_at_report_ = master_.cycle();
    inactive_requested_ = false;
    logger("ecpaird")->warn("the link guard took the links down after the cycle stood still for {} ms (last heartbeat cycle {}); "
                            "they come back once the cycle runs{}",
                            report.silence.count(), report.last_cycle, pair_ ? " and this member is INACTIVE" : "");
    check();
}

// Looks every few milliseconds, only while the links are down.
void LinkGuardResumePolicy::check() {
    if (!guard_.links_down()) return;
    const bool cycle_runs = master_.cycle() > cycle_at_report_;
    if (cycle_runs && pair_ && pair_->is_active() && !inactive_requested_) {
        logger("ecpaird")->warn("links down by the link guard while ACTIVE: becoming INACTIVE before they come up again");
        pair_->step_down();
        inactive_requested_ = true;
    }
    if (cycle_runs && (!pair_ || !pair_->is_active())) {
        logger("ecpaird")->info("the cycle runs{}: asking the link guard to bring the links up", pair_ ? " and this member is INACTIVE" : "");
        guard_.bring_links_up();
        return;
    }
    timer_.expires_after(kLookEvery);
    timer_.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) check();
    });
}

}  // namespace ecpair::daemon
