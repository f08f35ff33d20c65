#pragma once
// The link guard's events (ecpaird's side, LinkGuard): the guard took this
// member's links down or brought them up, the cycle resumed after a hang,
// the guard process ended. b = links (kMainLink, kRedLink bits), d = errno of
// a link the guard could not set.

#include "ecpair/master/event.hpp"

namespace ecpair::linkguard::events {

extern const master::EventType kLinkGuardLinksDown;  // a = DownReason, c = ms without a heartbeat
extern const master::EventType kLinkGuardResumed;    // c = ms the cycle stood still; the links stay down until ecpaird asks
extern const master::EventType kLinkGuardLinksUp;    // a = why (0 ecpaird started, 1 it may drive its links again), c = ms down
extern const master::EventType kLinkGuardGone;       // the guard process ended while ecpaird runs: a = its exit status

}  // namespace ecpair::linkguard::events
