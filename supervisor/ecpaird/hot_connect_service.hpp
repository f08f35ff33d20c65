#pragma once
// The Hot-Connect part of the operator API (control.proto Request kinds
// 25-39): the groups view, accept, force a topology change, block node,
// open blocked ports, port settings and programming an alias, each answered
// from HotConnect; a refusal names its error code first
// ("SlaveNotPresent: station 2201 is not on the bus").

#include "ecpair/control.pb.h"
#include "ecpair/hotconnect/hot_connect.hpp"

namespace ecpair::daemon {

class HotConnectService {
public:
    explicit HotConnectService(hotconnect::HotConnect& hot_connect) : hot_connect_(hot_connect) {}

    control::Response handle(const control::Request& request);
    void fill_summary(control::HotConnectSummary& out) const;

private:
    control::HotConnectGroupsReply groups() const;

    hotconnect::HotConnect& hot_connect_;
};

}  // namespace ecpair::daemon
