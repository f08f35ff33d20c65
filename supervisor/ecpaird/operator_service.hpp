#pragma once
// Answers the operator API (control.proto) for one ecpaird: the status view
// (states, ring, links, cycle timing, frame counters, slaves, a few process
// image variables, the demo's loopback check, the pair and its supervisor),
// master state requests and the pair's commands (red state, switchover,
// force standby).

#include <string>

#include "demo_application.hpp"
#include "hot_connect_service.hpp"
#include "ecpair/config/daemon_settings.hpp"
#include "ecpair/control/control_server.hpp"
#include "ecpair/linkguard/link_guard.hpp"
#include "ecpair/master/cycle_thread.hpp"
#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/redundancy/redundancy_controller.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"
#include "ecpair/supervisor/supervisor.hpp"
#include "ecpair/tap_bridge/tap_bridge.hpp"

namespace ecpair::daemon {

class OperatorService final : public control::ControlHandler {
public:
    OperatorService(const config::DaemonSettings& settings, master::Master& master,
                    sequencer::MasterStateMachine& state_machine, const master::CycleThread& cycle_thread,
                    const DemoApplication& demo, redundancy::RedundancyController* redundancy,
                    supervisor::Supervisor* supervisor, HotConnectService& hot_connect)
        : settings_(settings),
          master_(master),
          state_machine_(state_machine),
          cycle_thread_(cycle_thread),
          demo_(demo),
          redundancy_(redundancy),
          supervisor_(supervisor),
          hot_connect_(hot_connect) {}

    control::StatusReply status(const control::StatusRequest& request) override;
    std::optional<std::string> set_master_state(const control::SetMasterStateRequest& request) override;
    std::optional<std::string> set_red_state(const control::SetRedStateRequest& request) override;
    control::ImageHistoryReply image_history(const control::ImageHistoryRequest& request) override;
    void set_tap_bridge(const tap_bridge::TapBridge* bridge) { tap_bridge_ = bridge; }
    std::optional<std::string> switchover(const control::SwitchoverRequest& request) override;
    std::optional<std::string> force_standby(const control::ForceStandbyRequest& request) override;
    void set_link_guard(const linkguard::LinkGuard* guard) { link_guard_ = guard; }
    control::Response hot_connect(const control::Request& request) override { return hot_connect_.handle(request); }

private:
    void add_supervisor_status(const redundancy::RedundancySnapshot& pair, control::SupervisorStatus& out) const;

    const config::DaemonSettings& settings_;
    master::Master& master_;
    sequencer::MasterStateMachine& state_machine_;
    const master::CycleThread& cycle_thread_;
    const DemoApplication& demo_;
    redundancy::RedundancyController* redundancy_;  // null outside a pair
    supervisor::Supervisor* supervisor_;            // null outside a pair
    const tap_bridge::TapBridge* tap_bridge_ = nullptr;  // null without a tap block
    const linkguard::LinkGuard* link_guard_ = nullptr;  // null when off
    HotConnectService& hot_connect_;
};

// The event as the operator API carries it.
control::EventMessage to_message(const master::EventReport& report, const master::EventDescriber& describer);

}  // namespace ecpair::daemon
