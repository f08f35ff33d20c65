#include "link_guard_status.hpp"

#include <fmt/format.h>

namespace ecpair::daemon {

void fill_link_guard_status(const linkguard::LinkGuard* guard, control::LinkGuardStatus& out) {
    out.set_enabled(guard != nullptr);
    if (guard == nullptr) return;
    const auto s = guard->status();
    out.set_running(s.running);
    out.set_links_down(s.links_down);
    out.set_hang_timeout_ms(static_cast<std::uint32_t>(s.hang_timeout.count()));
    out.set_links_taken_down(s.links_taken_down);
    out.set_links_brought_up(s.links_brought_up);
    out.set_max_heartbeat_gap_ms(static_cast<double>(s.max_heartbeat_gap.count()) / 1000.0);
    if (s.last_down) {
        const auto& d = *s.last_down;
        out.set_last_action(fmt::format("{} down after cycle {}: {}, {} ms without a heartbeat{}",
                                        linkguard::links_text(d.links), d.last_cycle, linkguard::describe(d.reason),
                                        d.silence.count(),
                                        d.error != 0 ? fmt::format(" (some failed: errno {})", d.error) : ""));
    }
}

}  // namespace ecpair::daemon
