#include "ecpair/master/events.hpp"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "ecpair/master/frame_tracker.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::master {
namespace {

std::string role_name(std::uint32_t role) { return role == 0 ? "MAIN" : "RED"; }

std::string state_name(std::uint32_t state) { return wire::al_state_name(static_cast<std::uint8_t>(state)); }

std::string guarded_links(std::uint32_t links) {
    if (links == 3) return "MAIN and RED";
    if (links == 1) return "MAIN";
    if (links == 2) return "RED";
    return "no link";
}

std::string link_guard_failure(std::uint32_t error) {
    return error == 0 ? std::string() : fmt::format(" (failed for some: {})", std::strerror(static_cast<int>(error)));
}

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

std::string lost_frame_text(const Event& e) {
    const auto d = LostFrameDetail::decode(e);
    switch (static_cast<FrameKind>(e.a)) {
        case FrameKind::Cyclic:
            return fmt::format("cyclic frame {} ({}) lost ({}): this cycle's inputs keep their last values",
                               e.b + 1, state_name(d.master_state), d.copies_text());
        case FrameKind::Acyclic:
            return fmt::format("acyclic frame lost ({} at 0x{:08x}, {} bytes, {} datagram(s); {}): its requests are sent "
                               "again until their timeout",
                               wire::to_string(d.first_command), d.first_address, d.first_length, d.datagrams,
                               d.copies_text());
        case FrameKind::MasterRed: break;
    }
    return fmt::format("frame lost (kind {}, index {})", e.a, e.b);
}

std::string ms_text(std::uint32_t ms) { return fmt::format("{} ms", ms); }

std::string comm_timeout_text(const Event& e) {
    static constexpr const char* kAction[] = {
        "taking over hot from the mirror (no INIT, the slaves stay in their state)",
        "taking over cold (no fresh mirror: the slaves start over from INIT)",
        "NOT taking over: this member is forced to standby",
        "NOT taking over: the partner ran another ENI or other pair parameters",
        "NOT taking over: both own links are down (isolated)"};
    return fmt::format("no Cyclic Master Red Frame from the ACTIVE partner for {} (comm timeout {}{}): {}",
                       ms_text(e.a), ms_text(e.b), e.d != 0 ? ", shortened because a link went down" : "",
                       kAction[std::min<std::uint32_t>(e.c, 4)]);
}

}  // namespace

std::string_view to_string(HandOffRefusal refusal) {
    switch (refusal) {
        case HandOffRefusal::None: return "";
        case HandOffRefusal::PartnerNotAnswering: return "the partner does not answer in the CMF";
        case HandOffRefusal::PartnerCold: return "the partner is no hot standby (it does not mirror this master)";
        case HandOffRefusal::PartnerForced: return "the partner is forced to standby";
        case HandOffRefusal::PartnerDiffers: return "the partner runs another ENI or other pair parameters";
        case HandOffRefusal::PartnerLinkDown: return "one of the partner's links is down";
        case HandOffRefusal::NotAcknowledged: return "the partner did not acknowledge the hand-off in time";
        case HandOffRefusal::NotActive: return "this master is not ACTIVE";
        case HandOffRefusal::AlreadyRunning: return "a hand-off is already under way";
        case HandOffRefusal::PartnerLost: return "the partner went silent";
        case HandOffRefusal::ForcedStandby:
            return "this master was forced to standby (the ACTIVE keeps the bus unless it has stepped down already)";
    }
    return "unknown reason";
}

namespace {

std::string_view refusal_text(std::uint32_t code) { return to_string(static_cast<HandOffRefusal>(code)); }

std::string handoff_text(const Event& e) {
    switch (static_cast<HandOffPhase>(e.a)) {
        case HandOffPhase::Announced:
            return fmt::format("switchover: hand-off to the partner announced for cycle {}", e.b);
        case HandOffPhase::Acknowledged:
            return fmt::format("switchover: the partner acknowledged, it takes over at cycle {}", e.b);
        case HandOffPhase::SteppedDown:
            return fmt::format("switchover: last cycle sent, now INACTIVE; the partner sends from cycle {}", e.b);
        case HandOffPhase::TakenOver:
            return fmt::format("switchover: took over at cycle {} as the partner announced (hot, no cycle lost)", e.b);
        case HandOffPhase::Cancelled:
            return fmt::format("switchover for cycle {} cancelled: {}", e.b, refusal_text(e.c));
        case HandOffPhase::Refused: return fmt::format("switchover refused: {}", refusal_text(e.c));
    }
    return "hand-off";
}

std::string_view rule_text(std::uint32_t code) {
    switch (static_cast<RuleCode>(code)) {
        case RuleCode::SlavesReached: return "the master that reaches more slaves keeps the bus";
        case RuleCode::Epoch: return "same reach: the master that has owned the bus longer (older epoch) keeps it";
        case RuleCode::Mac: return "same reach and epoch: the lower MAIN MAC keeps the bus";
        case RuleCode::None: return "";
    }
    return "";
}

std::string collision_text(const Event& e) {
    const auto backoff = fmt::format("{:.1f} ms", static_cast<double>(e.b) / 1000.0);
    switch (static_cast<BackoffCode>(e.c)) {
        case BackoffCode::Random:
            return fmt::format("collision: another master sends on this bus (round {}); stopped sending, backing off "
                               "{} (random) before listening",
                               e.a, backoff);
        case BackoffCode::Preferred:
            return fmt::format("collision: another master sends on this bus (round {}); stopped sending, backing off "
                               "{}: this master is preferred ({})",
                               e.a, backoff, rule_text(e.d));
        case BackoffCode::Deferring:
            return fmt::format("collision: another master sends on this bus (round {}); stopped sending, deferring "
                               "{}: the other master is preferred ({})",
                               e.a, backoff, rule_text(e.d));
    }
    return "collision";
}

std::string arbitration_text(const Event& e) {
    const auto theirs = e.d == 0xFFFF ? std::string("unknown") : std::to_string(e.d);
    switch (static_cast<ArbitrationOutcome>(e.a)) {
        case ArbitrationOutcome::TookBusAfterListening:
            return fmt::format("arbitration: no ACTIVE master heard while listening: this master takes the bus "
                               "(epoch {})",
                               e.b);
        case ArbitrationOutcome::YieldedToActive:
            return fmt::format("arbitration: an ACTIVE master is heard (it reaches {} slaves, this one {}): standing "
                               "by as INACTIVE",
                               theirs, e.c);
        case ArbitrationOutcome::KeptBusAfterCollision:
            return fmt::format("arbitration: backoff over in silence: this master owns the bus (epoch {}, reaches {} "
                               "slaves, the other {})",
                               e.b, e.c, theirs);
    }
    return "arbitration settled";
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
        case EventKind::CycleStall: return "cycle-stall";
        case EventKind::CoeEmergency: return "coe-emergency";
        case EventKind::CommTimeout: return "comm-timeout";
        case EventKind::AllLinksLost: return "all-links-lost";
        case EventKind::LinksRestored: return "links-restored";
        case EventKind::FramesNotReturning: return "frames-not-returning";
        case EventKind::FramesReturning: return "frames-returning";
        case EventKind::Collision: return "collision";
        case EventKind::ArbitrationSettled: return "arbitration-settled";
        case EventKind::StandbyForced: return "standby-forced";
        case EventKind::NoActiveMaster: return "no-active-master";
        case EventKind::LinkGuardLinksDown: return "link-guard-links-down";
        case EventKind::LinkGuardResumed: return "link-guard-resumed";
        case EventKind::LinkGuardLinksUp: return "link-guard-links-up";
        case EventKind::LinkGuardGone: return "link-guard-gone";
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
        case EventKind::FrameLost: return prefix + lost_frame_text(e);
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
        case EventKind::PartnerLost:
            return prefix + fmt::format("partner lost: its last answer in the CMF is {} ms old; still ACTIVE, "
                                        "no hot standby until it answers again",
                                        e.a);
        case EventKind::PartnerFound:
            return prefix + (e.a == 0 ? std::string("partner found: it answers in the CMF")
                                      : fmt::format("partner found again after {} ms without an answer", e.a));
        case EventKind::PartnerMismatch: return prefix + "partner differs in: " + partner_differences(e.a);
        case EventKind::Takeover:
            return prefix + (e.a != 0 ? fmt::format("hot takeover: now ACTIVE in {}", state_name(e.b))
                                      : std::string("cold takeover: now ACTIVE, starting from INIT"));
        case EventKind::HandOff: return prefix + handoff_text(e);
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
        case EventKind::CycleStall:
            return prefix + fmt::format("{} cycle deadline(s) passed without a cycle (it woke {} µs after its "
                                        "deadline and ended that much later): the machine did not run this master "
                                        "in time (other processes or the host), or the cycle ran that long; the "
                                        "skipped cycles sent nothing",
                                        e.b, e.a);
        case EventKind::CoeEmergency:
            return prefix + fmt::format("slave {}: {}", e.a, coe_emergency_text(e));
        case EventKind::CommTimeout: return prefix + comm_timeout_text(e);
        case EventKind::AllLinksLost:
            return prefix + (e.a != 0 ? std::string("all links lost (MAIN and RED down): this ACTIVE master becomes "
                                                    "INACTIVE, its partner may take over")
                                      : std::string("all links lost (MAIN and RED down): isolated, will not take over"));
        case EventKind::LinksRestored: return prefix + "a link is back: listening for an ACTIVE master again";
        case EventKind::FramesNotReturning:
            return prefix + fmt::format(
                                "none of this master's frames came back on MAIN or RED for {} cycles: the ring is open "
                                "at both ends{}; still sending",
                                e.a,
                                e.b != 0 ? " - most likely the failed partner's links are still up and swallow the "
                                           "frames (its link guard did not take them down: pull its cables)"
                                         : " (both cables, or a partner that swallows the frames)");
        case EventKind::FramesReturning: return prefix + fmt::format("frames come back again, after {} cycles", e.a);
        case EventKind::Collision: return prefix + collision_text(e);
        case EventKind::ArbitrationSettled: return prefix + arbitration_text(e);
        case EventKind::StandbyForced:
            return prefix + (e.a != 0 ? std::string("forced to standby: this master will not become ACTIVE")
                                      : std::string("standby no longer forced: this master may become ACTIVE"));
        case EventKind::NoActiveMaster: {
            static constexpr const char* kWhy[] = {
                "this member is forced to standby and no ACTIVE partner is heard",
                "the only master heard runs another ENI or other pair parameters and has gone silent",
                "both of this member's links are down"};
            return prefix + fmt::format("NO MASTER IS ACTIVE: {}; the slaves get no process data",
                                        kWhy[std::min<std::uint32_t>(e.a, 2)]);
        }
        case EventKind::LinkGuardLinksDown:
            return prefix + fmt::format("link guard took {} down: {} ({} ms without a heartbeat){}", guarded_links(e.b),
                                        e.a == 1 ? "the cycle stood still" : "ecpaird is stopping", e.c,
                                        link_guard_failure(e.d));
        case EventKind::LinkGuardResumed:
            return prefix + fmt::format("the cycle advances again after standing still for {} ms; the link guard keeps "
                                        "the links down until this master may drive them",
                                        e.c);
        case EventKind::LinkGuardLinksUp:
            return prefix + fmt::format("link guard brought {} up: {}{}", guarded_links(e.b),
                                        e.a == 0 ? "ecpaird started"
                                                 : fmt::format("this master may drive its links again (down for {} ms)", e.c),
                                        link_guard_failure(e.d));
        case EventKind::LinkGuardGone:
            return prefix + fmt::format("the link guard process ended (status {}): the links are no longer guarded", e.a);
    }
    return prefix + "unknown event";
}

namespace {

constexpr std::uint32_t kSentMain = 1u << 28;
constexpr std::uint32_t kSentRed = 1u << 29;
constexpr std::uint32_t kMainReturned = 1u << 30;
constexpr std::uint32_t kRedReturned = 1u << 31;
constexpr std::uint32_t kLengthMask = 0x7FF;

}  // namespace

void LostFrameDetail::encode_into(Event& event) const {
    event.c = static_cast<std::uint32_t>(first_command) | std::uint32_t{datagrams} << 8 |
              (std::uint32_t{first_length} & kLengthMask) << 16 | (sent_main ? kSentMain : 0u) |
              (sent_red ? kSentRed : 0u) | (main_returned ? kMainReturned : 0u) | (red_returned ? kRedReturned : 0u);
    // A cyclic frame's content is in the plan: d says the state it was built for.
    event.d = event.a == static_cast<std::uint32_t>(FrameKind::Cyclic) ? std::uint32_t{master_state} : first_address;
}

std::string LostFrameDetail::copies_text() const {
    const auto one = [](bool sent, bool returned) { return !sent ? "not sent" : returned ? "came back" : "missing"; };
    return fmt::format("MAIN copy {}, RED copy {}", one(sent_main, main_returned), one(sent_red, red_returned));
}

LostFrameDetail LostFrameDetail::decode(const Event& event) {
    LostFrameDetail d;
    const bool cyclic = event.a == static_cast<std::uint32_t>(FrameKind::Cyclic);
    d.master_state = cyclic ? static_cast<std::uint8_t>(event.d) : std::uint8_t{0};
    d.first_address = cyclic ? 0 : event.d;
    d.first_command = static_cast<wire::Command>(event.c & 0xFF);
    d.datagrams = static_cast<std::uint8_t>(event.c >> 8);
    d.first_length = static_cast<std::uint16_t>((event.c >> 16) & kLengthMask);
    d.sent_main = (event.c & kSentMain) != 0;
    d.sent_red = (event.c & kSentRed) != 0;
    d.main_returned = (event.c & kMainReturned) != 0;
    d.red_returned = (event.c & kRedReturned) != 0;
    return d;
}

EventQueue::EventQueue(std::size_t capacity) : ring_(capacity) {}

void EventQueue::raise(EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    const auto* counter = cycle_counter_.load();
    push(Event{kind, counter != nullptr ? counter->load() : 0, std::chrono::system_clock::now(), a, b, c, d});
}

void EventQueue::attach_cycle_counter(const std::atomic<std::uint64_t>* counter) { cycle_counter_.store(counter); }

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

std::string coe_emergency_text(const Event& e) {
    const auto code = static_cast<std::uint16_t>(e.b);
    return fmt::format("CoE emergency 0x{:04x} ({}), error register 0x{:02x}, data {:02x} {:02x} {:02x} {:02x} {:02x}",
                       code, wire::emergency_error_class(code), (e.b >> 16) & 0xFF, e.c & 0xFF, (e.c >> 8) & 0xFF,
                       (e.c >> 16) & 0xFF, e.c >> 24, e.d & 0xFF);
}

}  // namespace ecpair::master
