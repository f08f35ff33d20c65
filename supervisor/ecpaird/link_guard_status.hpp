#pragma once
// The link guard's part of the operator status (StatusReply.link_guard).

#include "ecpair/control.pb.h"
#include "ecpair/linkguard/link_guard.hpp"

namespace ecpair::daemon {

// `guard` null: the link guard is off.
void fill_link_guard_status(const linkguard::LinkGuard* guard, control::LinkGuardStatus& out);

}  // namespace ecpair::daemon
