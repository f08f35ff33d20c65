// Hot-Connect's event texts: how a change ended, which groups are there
// (of how many), and what happened to a port's loop and why.

#include "ecpair/hotconnect/hot_connect_events.hpp"

#include <fmt/format.h>

namespace ecpair::hotconnect {
namespace {

using master::Event;
using master::EventDescriber;

std::string result_text(std::uint32_t result) {
    return result <= static_cast<std::uint32_t>(TopologyResult::Cancelled)
               ? std::string(to_string(static_cast<TopologyResult>(result)))
               : fmt::format("result {}", result);
}

std::string_view loop_text(std::uint32_t setting) {
    switch (setting & 3) {
        case 0: return "auto";
        case 1: return "auto-close";
        case 2: return "open";
        default: return "closed";
    }
}

std::string_view port_reason_text(std::uint32_t reason) {
    switch (static_cast<PortLoopReason>(reason)) {
        case PortLoopReason::BorderClose: return "border close: no group may join there";
        case PortLoopReason::BlockNode: return "block node: cut off what hangs behind it";
        case PortLoopReason::OpenBlocked: return "blocked port opened again";
        case PortLoopReason::ByOperator: break;
    }
    return "operator request";
}

std::string topology_change_done(const Event& e, const EventDescriber&) {
    return fmt::format("topology change done: {}; {} of {} optional group(s) present; {} WKC deviation(s) put down to "
                       "the change",
                       result_text(e.a), e.b, e.c, e.d);
}

std::string groups_text(std::string_view what, const Event& e) {
    return fmt::format("{}: {}; {} group(s) present of {} (mask 0x{:08x})", what, result_text(e.a), e.c, e.b, e.d);
}
std::string detect_add_groups(const Event& e, const EventDescriber&) { return groups_text("groups added", e); }
std::string probe_all_groups(const Event& e, const EventDescriber&) { return groups_text("groups probed", e); }

std::string accept_pending(const Event& e, const EventDescriber&) {
    return fmt::format("{} Hot-Connect group(s) found (mask 0x{:08x}): waiting for an accept", e.a, e.b);
}

std::string port_loop_changed(const Event& e, const EventDescriber&) {
    return fmt::format("station {} port {}: {} ({})", e.a, static_cast<char>('A' + (e.b & 3)), loop_text(e.c),
                       port_reason_text(e.d));
}

}  // namespace

std::string_view to_string(TopologyResult result) {
    switch (result) {
        case TopologyResult::Ok: return "ok";
        case TopologyResult::GroupsRefused: return "groups refused (a mismatch)";
        case TopologyResult::MandatoryMissing: return "a mandatory slave is missing";
        case TopologyResult::BringUpFailed: return "a group did not reach the master state";
        case TopologyResult::ScanFailed: return "the bus could not be scanned";
        case TopologyResult::Timeout: return "the bus did not settle within the detection timeout";
        case TopologyResult::Cancelled: return "cancelled";
    }
    return "?";
}

namespace events {

constinit const master::EventType kTopologyChangeDone{"topology-change-done", topology_change_done};
constinit const master::EventType kDetectAddGroups{"detect-add-groups", detect_add_groups};
constinit const master::EventType kProbeAllGroups{"probe-all-groups", probe_all_groups};
constinit const master::EventType kHotConnectAcceptPending{"hot-connect-accept-pending", accept_pending};
constinit const master::EventType kPortLoopChanged{"port-loop-changed", port_loop_changed};

}  // namespace events
}  // namespace ecpair::hotconnect
