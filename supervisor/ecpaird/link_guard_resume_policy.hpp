#pragma once
// What ecpaird does when its link guard took the links down because the
// cycle stood still (a hang, SIGSTOP): once the cycle advances again, a pair
// member that is ACTIVE asks its Supervisor to step down (its partner may
// have taken over meanwhile; two ACTIVE masters on one ring must not
// happen), and only when it is INACTIVE are the links brought up again; the
// Supervisor then listens and arbitrates as after any link loss. A single
// master brings them up as soon as its cycle runs. Each step is logged.
//
// The glue between LinkGuard's two hooks (set_on_links_down(),
// bring_links_up()) and the role; a Supervisor that wants to decide this
// itself takes the hooks instead.

#include <cstdint>
#include <functional>
#include <optional>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

#include "ecpair/linkguard/link_guard.hpp"
#include "ecpair/master/master.hpp"

namespace ecpair::daemon {

// A pair member's role, as the policy needs it.
struct PairRole {
    std::function<bool()> is_active;
    std::function<void()> step_down;  // INACTIVE at the next cycle boundary (Supervisor::request_role)
};

class LinkGuardResumePolicy {
public:
    // Installs itself as `guard`'s on_links_down. `pair` is empty outside a pair.
    LinkGuardResumePolicy(boost::asio::io_context& io, linkguard::LinkGuard& guard, const master::Master& master,
                          std::optional<PairRole> pair);

private:
    void on_links_down(const linkguard::LinksDownReport& report);
    void check();

    linkguard::LinkGuard& guard_;
    const master::Master& master_;
    std::optional<PairRole> pair_;
    boost::asio::steady_timer timer_;
    std::uint64_t cycle_at_report_ = 0;
    bool inactive_requested_ = false;
    static constexpr std::chrono::milliseconds kLookEvery{5};
};

}  // namespace ecpair::daemon
