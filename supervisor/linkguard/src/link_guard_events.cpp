// The link guard's event texts: which links, why, for how long, and what
// failed.

#include "ecpair/linkguard/link_guard_events.hpp"

#include <cstring>

#include <fmt/format.h>

#include "ecpair/linkguard/guard_protocol.hpp"

namespace ecpair::linkguard {
namespace {

using master::Event;
using master::EventDescriber;

std::string links_of(const Event& e) { return links_text(static_cast<std::uint8_t>(e.b)); }

std::string failure_text(std::uint32_t error) {
    return error == 0 ? std::string() : fmt::format(" (failed for some: {})", std::strerror(static_cast<int>(error)));
}

std::string links_down(const Event& e, const EventDescriber&) {
    return fmt::format("link guard took {} down: {} ({} ms without a heartbeat){}", links_of(e),
                       e.a == static_cast<std::uint32_t>(DownReason::HeartbeatStopped) ? "the cycle stood still"
                                                                                       : "ecpaird is stopping",
                       e.c, failure_text(e.d));
}

std::string resumed(const Event& e, const EventDescriber&) {
    return fmt::format("the cycle advances again after standing still for {} ms; the link guard keeps the links down "
                       "until this master may drive them",
                       e.c);
}

std::string links_up(const Event& e, const EventDescriber&) {
    return fmt::format("link guard brought {} up: {}{}", links_of(e),
                       e.a == 0 ? "ecpaird started"
                                : fmt::format("this master may drive its links again (down for {} ms)", e.c),
                       failure_text(e.d));
}

std::string gone(const Event& e, const EventDescriber&) {
    return fmt::format("the link guard process ended (status {}): the links are no longer guarded", e.a);
}

}  // namespace

namespace events {

constinit const master::EventType kLinkGuardLinksDown{"link-guard-links-down", links_down};
constinit const master::EventType kLinkGuardResumed{"link-guard-resumed", resumed};
constinit const master::EventType kLinkGuardLinksUp{"link-guard-links-up", links_up};
constinit const master::EventType kLinkGuardGone{"link-guard-gone", gone};

}  // namespace events
}  // namespace ecpair::linkguard
