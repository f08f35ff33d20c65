#pragma once
// What ecpaird does when its link guard took the links down because the
// cycle stood still (a hang, SIGSTOP), until the Supervisor takes this
// decision: once the cycle advances again, a pair member that is ACTIVE asks
// to become INACTIVE (its partner may have taken over meanwhile; two ACTIVE
// masters on one ring must not happen), and only when it is INACTIVE are the
// links brought up again. A single master brings them up as soon as its
// cycle runs. Each step is logged.
//
// The Supervisor replaces this class: it gets LinkGuard::set_on_links_down()
// and calls LinkGuard::bring_links_up() when it decided the role.

#include <cstdint>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

#include "ecpair/linkguard/link_guard.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/redundancy/redundancy_controller.hpp"

namespace ecpair::daemon {

class LinkGuardResumePolicy {
public:
    // Installs itself as `guard`'s on_links_down. `redundancy` is null outside a pair.
    LinkGuardResumePolicy(boost::asio::io_context& io, linkguard::LinkGuard& guard, const master::Master& master,
                          redundancy::RedundancyController* redundancy);

private:
    void on_links_down(const linkguard::LinksDownReport& report);
    void check();

    linkguard::LinkGuard& guard_;
    const master::Master& master_;
    redundancy::RedundancyController* redundancy_;
    boost::asio::steady_timer timer_;
    std::uint64_t cycle_at_report_ = 0;
    bool inactive_requested_ = false;
    static constexpr std::chrono::milliseconds kLookEvery{5};
};

}  // namespace ecpair::daemon
