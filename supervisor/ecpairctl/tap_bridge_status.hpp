#pragma once
// `ecpairctl status`: the TAP bridge's lines.

#include <ostream>

#include "ecpair/control.pb.h"

namespace ecpair::ctl {

// Prints nothing when the daemon has no TAP bridge.
void print_tap_bridge_status(std::ostream& out, const control::StatusReply& status);

}  // namespace ecpair::ctl
