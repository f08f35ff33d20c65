#include "ecpair/master/events.hpp"

#include <fmt/format.h>

#include "ecpair/wire/al_status.hpp"

namespace ecpair::master {
namespace {

std::string role_name(std::uint32_t role) { return role == 0 ? "MAIN" : "RED"; }

std::string state_name(std::uint32_t state) { return wire::al_state_name(static_cast<std::uint8_t>(state)); }

std::string partner_differences(std::uint32_t mask) {
    static constexpr std::pair<std::uint32_t, const char*> kNames[] = {
        {kDiffersEni, "ENI"},
        {kDiffersCycleTime, "cycle time"},
        {kDiffersCableRedundancy, "cable redundancy"},
        {kDiffersSplitLrw, "split_lrw"},
        {kDiffersMasterPdOut, "master_pd_out_size"},
        {kDiffersMasterPdIn, "master_pd_in_size"},
        {kDiffersUpdateSlavePdIn, "update_slave_pd_in"},
        {kDiffersUpdateSlavePdOut, "update_slave_pd_out"},
        {kDiffersMaxAcycFrames, "max_acyc_frames_per_cycle"},
        {kDiffersLayout, "the CMF layout (slave count or image sizes)"},
    };
    std::string text;
    for (const auto& [bit, name] : kNames) {
        if ((mask & bit) == 0) continue;
        if (!text.empty()) text += ", ";
        text += name;
    }
    return text.empty() ? std::string("something") : text;
}

std::string count_text(std::uint32_t count) { return count == 0xFFFF ? std::string("?") : fmt::format("{}", count); }

std::string topology_result_text(std::uint32_t result) {
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
    switch (reason) {
        case kPortBorderClose: return "border close: no group may join there";
        case kPortBlockNode: return "block node: cut off what hangs behind it";
        case kPortOpenBlocked: return "blocked port opened again";
        default: return "operator request";
    }
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

std::string_view to_string(EventKind kind) {
    switch (kind) {
        case EventKind::MasterStateChanged: return "master-state-changed";
        case EventKind::CyclicWkcError: return "cyclic-wkc-error";
        case EventKind::FrameLost: return "frame-lost";
        case EventKind::LineBreak: return "line-break";
        case EventKind::LineRepaired: return "line-repaired";
        case EventKind::LinkDown: return "link-down";
        case EventKind::LinkUp: return "link-up";
        case EventKind::BusScanStatus: return "bus-scan-status";
        case EventKind::BusMismatch: return "bus-mismatch";
        case EventKind::SlavePresence: return "slave-presence";
        case EventKind::SlaveStateError: return "slave-state-error";
        case EventKind::TransitionFailed: return "transition-failed";
        case EventKind::FrameResponseError: return "frame-response-error";
        case EventKind::RedStateChanged: return "red-state-changed";
        case EventKind::PartnerLost: return "partner-lost";
        case EventKind::PartnerFound: return "partner-found";
        case EventKind::PartnerMismatch: return "partner-mismatch";
        case EventKind::Takeover: return "takeover";
        case EventKind::HandOff: return "hand-off";
        case EventKind::TopologyVerified: return "topology-verified";
        case EventKind::TopologyChangeDetected: return "topology-change-detected";
        case EventKind::TopologyChangeDone: return "topology-change-done";
        case EventKind::DetectAddGroups: return "detect-add-groups";
        case EventKind::ProbeAllGroups: return "probe-all-groups";
        case EventKind::BusMismatchIdentification: return "bus-mismatch-identification";
        case EventKind::BusMismatchPlace: return "bus-mismatch-place";
        case EventKind::HotConnectAcceptPending: return "hot-connect-accept-pending";
        case EventKind::SlaveIdentificationUpdated: return "slave-identification-updated";
        case EventKind::PortLoopChanged: return "port-loop-changed";
    }
    return "unknown-event";
}

std::string describe(const Event& e) {
    const auto prefix = fmt::format("cycle {}: ", e.cycle);
    switch (e.kind) {
        case EventKind::MasterStateChanged:
            return prefix + fmt::format("master state {} -> {}", state_name(e.a), state_name(e.b));
        case EventKind::CyclicWkcError:
            return prefix + fmt::format("cyclic WKC error in frame {} datagram {}: expected {}, received {}", e.a, e.b,
                                        e.c, e.d);
        case EventKind::FrameLost: return prefix + fmt::format("frame lost (kind {}, index {})", e.a, e.b);
        case EventKind::LineBreak:
            return prefix + (e.b != 0 ? fmt::format("line break after slave {} (slaves reachable from MAIN: {})", e.a, e.a)
                                      : std::string("line break"));
        case EventKind::LineRepaired: return prefix + "line repaired: the ring is closed";
        case EventKind::LinkDown: return prefix + fmt::format("link {} down", role_name(e.a));
        case EventKind::LinkUp: return prefix + fmt::format("link {} up", role_name(e.a));
        case EventKind::BusScanStatus:
            return prefix + fmt::format("bus scan: {} slave(s) found, {} configured, {}", e.a, e.b,
                                        e.c != 0 ? "match" : "MISMATCH");
        case EventKind::BusMismatch: return prefix + fmt::format("bus mismatch at position {}", e.a);
        case EventKind::SlavePresence:
            return prefix + fmt::format("slave {} {}", e.a, e.b != 0 ? "present" : "absent");
        case EventKind::SlaveStateError:
            return prefix + fmt::format("slave {} AL status {} code 0x{:04x} ({})", e.a,
                                        wire::AlStatus{static_cast<std::uint8_t>(e.b)}.to_string(), e.c,
                                        wire::al_status_code_text(static_cast<std::uint16_t>(e.c)));
        case EventKind::TransitionFailed:
            return prefix + fmt::format("transition {} -> {} failed{}", state_name(e.a), state_name(e.b),
                                        e.c == 0xFFFF ? std::string() : fmt::format(" at slave {}", e.c));
        case EventKind::FrameResponseError:
            return prefix + fmt::format("frame response error on {}: {}", role_name(e.b),
                                        e.a == static_cast<std::uint32_t>(FrameResponseReason::ForeignSourceMac)
                                            ? "foreign source MAC"
                                        : e.a == static_cast<std::uint32_t>(FrameResponseReason::Malformed)
                                            ? "malformed frame"
                                            : "late or stale frame");
        case EventKind::RedStateChanged:
            return prefix + fmt::format("redundancy state {} -> {}", e.a == 0 ? "INACTIVE" : "ACTIVE",
                                        e.b == 0 ? "INACTIVE" : "ACTIVE");
        case EventKind::PartnerLost: return prefix + "partner lost";
        case EventKind::PartnerFound: return prefix + "partner found";
        case EventKind::PartnerMismatch: return prefix + "partner differs in: " + partner_differences(e.a);
        case EventKind::Takeover:
            return prefix + (e.a != 0 ? fmt::format("hot takeover: now ACTIVE in {}", state_name(e.b))
                                      : std::string("cold takeover: now ACTIVE, starting from INIT"));
        case EventKind::HandOff: return prefix + "hand-off";
        case EventKind::TopologyVerified:
            return prefix + fmt::format("background scan {} the mirrored topology", e.a != 0 ? "confirms" : "contradicts");
        case EventKind::TopologyChangeDetected:
            return prefix + fmt::format("topology change: the AL status BRD counts {} slave(s), {} before", count_text(e.b),
                                        count_text(e.a));
        case EventKind::TopologyChangeDone:
            return prefix + fmt::format("topology change done: {}; {} of {} optional group(s) present; {} WKC "
                                        "deviation(s) put down to the change",
                                        topology_result_text(e.a), e.b, e.c, e.d);
        case EventKind::DetectAddGroups:
        case EventKind::ProbeAllGroups:
            return prefix + fmt::format("{}: {}; {} group(s) present of {} (mask 0x{:08x})",
                                        e.kind == EventKind::DetectAddGroups ? "groups added" : "groups probed",
                                        topology_result_text(e.a), e.c, e.b, e.d);
        case EventKind::BusMismatchIdentification:
            return prefix + fmt::format("bus mismatch at position {}: identification 0x{:04x} expected {}, read {}", e.a,
                                        e.b, e.d, e.c > 0xFFFF ? std::string("nothing") : fmt::format("{}", e.c));
        case EventKind::BusMismatchPlace:
            return prefix + fmt::format("bus mismatch at position {}: it hangs on station {} port {} (position {})", e.a,
                                        e.b, static_cast<char>('A' + (e.c & 3)), e.d);
        case EventKind::HotConnectAcceptPending:
            return prefix + fmt::format("{} Hot-Connect group(s) found (mask 0x{:08x}): waiting for an accept", e.a, e.b);
        case EventKind::SlaveIdentificationUpdated:
            return prefix + fmt::format("slave {}: AL status code 0x0061 (device identification value updated): its "
                                        "ID selector is its station alias now ({}); re-initialised",
                                        e.a, e.b);
        case EventKind::PortLoopChanged:
            return prefix + fmt::format("station {} port {}: {} ({})", e.a, static_cast<char>('A' + (e.b & 3)),
                                        loop_text(e.c), port_reason_text(e.d));
    }
    return prefix + "unknown event";
}

EventQueue::EventQueue(std::size_t capacity) : ring_(capacity) {}

void EventQueue::push(const Event& event) {
    {
        std::lock_guard lock(mutex_);
        if (count_ == ring_.size()) {
            ++dropped_;
            return;
        }
        ring_[(head_ + count_) % ring_.size()] = event;
        ++count_;
    }
    ready_.notify_one();
}

std::vector<Event> EventQueue::pop_all(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return count_ > 0; });
    std::vector<Event> out;
    out.reserve(count_);
    while (count_ > 0) {
        out.push_back(ring_[head_]);
        head_ = (head_ + 1) % ring_.size();
        --count_;
    }
    return out;
}

std::uint64_t EventQueue::dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
}

}  // namespace ecpair::master
