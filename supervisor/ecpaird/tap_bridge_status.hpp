#pragma once
// The TAP bridge's part of the operator API's status (control.proto TapBridgeStatus).

#include "ecpair/control.pb.h"
#include "ecpair/tap_bridge/tap_bridge.hpp"

namespace ecpair::daemon {

void fill_tap_bridge_status(const tap_bridge::TapBridge& bridge, control::TapBridgeStatus& out);

}  // namespace ecpair::daemon
