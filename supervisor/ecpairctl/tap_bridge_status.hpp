#pragma once
// `ecpairctl status`: the TAP bridge's section (its lines, its JSON).

#include <ostream>

#include "ecpair/control.pb.h"
#include "json_writer.hpp"

namespace ecpair::ctl {

// Prints nothing when the daemon has no TAP bridge.
void print_tap_bridge_status(std::ostream& out, const control::StatusReply& status);
// The "tap_bridge" key of `status --json` (null without a TAP bridge).
void write_tap_bridge_json(JsonWriter& json, const control::StatusReply& status);

}  // namespace ecpair::ctl
