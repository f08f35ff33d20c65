// The master's events and their texts: what happened, to which frame or
// slave (named through the EventDescriber), and what the master did about
// it. The kinds that repeat every cycle or frame while a fault lasts name
// their subject, so that a fault is summarised instead of logged per cycle.

#include "ecpair/master/master_events.hpp"

#include <fmt/format.h>

#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/frame_tracker.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::master {
namespace {

std::string state_name(std::uint32_t state) { return wire::al_state_name(static_cast<std::uint8_t>(state)); }

std::string_view role_name(std::uint32_t role) { return to_string(static_cast<LinkRole>(role != 0 ? 1 : 0)); }

std::string count_text(std::uint32_t count) { return count == 0xFFFF ? std::string("?") : fmt::format("{}", count); }

std::uint64_t pair_of(std::uint32_t high, std::uint32_t low) { return std::uint64_t{high} << 32 | low; }

std::string master_state_changed(const Event& e, const EventDescriber&) {
    return fmt::format("master state {} -> {}", state_name(e.a), state_name(e.b));
}

std::string cyclic_wkc_error(const Event& e, const EventDescriber& describer) {
    const auto what = fmt::format("WKC {}, expected {}", e.d, e.c);
    const PlannedDatagram* d = describer.cyclic_datagram(e.a, e.b);
    if (d == nullptr) {
        return fmt::format("cyclic frame {} datagram {} came back with {}: the cycle's inputs are marked invalid",
                           e.a + 1, e.b + 1, what);
    }
    std::string who;
    switch (wire::addressing_of(d->command)) {
        case wire::Addressing::Logical: who = describer.slaves_mapping(d->address, d->length); break;
        case wire::Addressing::Broadcast:
            if (e.d < e.c) who = fmt::format("; {} of the {} slaves did not answer", e.c - e.d, e.c);
            break;
        case wire::Addressing::Configured:
            who = describer.addressed_station(static_cast<std::uint16_t>(d->address & 0xFFFF));
            break;
        default: break;
    }
    return fmt::format("cyclic frame {} datagram {} ({}) came back with {}{}: the cycle's inputs are marked invalid",
                       e.a + 1, e.b + 1, describer.datagram(*d), what, who);
}
std::uint64_t wkc_error_subject(const Event& e) { return pair_of(e.a, e.b); }  // the datagram

std::string frame_lost(const Event& e, const EventDescriber& describer) {
    const auto d = LostFrameDetail::decode(e);
    switch (static_cast<FrameKind>(e.a)) {
        case FrameKind::Cyclic:
            return fmt::format("{} lost ({}): this cycle's inputs keep their last values",
                               describer.cyclic_frame(e.b, d.master_state), d.copies_text());
        case FrameKind::Acyclic: {
            const std::string more = d.datagrams > 1 ? fmt::format(" and {} more datagram(s)", d.datagrams - 1) : "";
            return fmt::format("acyclic frame lost: {} to {}, {} bytes{} ({}): its requests are sent again until their "
                               "timeout",
                               wire::to_string(d.first_command), describer.acyclic_target(d.first_command, d.first_address),
                               d.first_length, more, d.copies_text());
        }
        case FrameKind::MasterRed: break;
    }
    return fmt::format("frame lost (kind {}, index {})", e.a, e.b);
}
// A cyclic frame by its number; the acyclic frames (a batch each) together.
std::uint64_t frame_lost_subject(const Event& e) {
    return static_cast<FrameKind>(e.a) == FrameKind::Cyclic ? pair_of(e.a, e.b) : pair_of(e.a, 0);
}

std::string line_break(const Event& e, const EventDescriber& describer) {
    const std::size_t slaves = describer.slave_count();
    if (e.b == 0) return "line break";
    if (slaves == 0) return fmt::format("line break after slave {} (slaves reachable from MAIN: {})", e.a, e.a);
    if (e.a == 0) return "line break at the MAIN cable: every slave is reached from RED";
    if (e.a >= slaves) {
        return fmt::format("line break after slave {} {}, at the RED cable: every slave is reached from MAIN", e.a,
                           describer.slave_at_position(e.a));
    }
    return fmt::format("line break after slave {} {}, before {}: slaves 1-{} are reached from MAIN, {}-{} from RED; "
                       "every slave stays in the cycle",
                       e.a, describer.slave_at_position(e.a), describer.slave_at_position(e.a + 1), e.a, e.a + 1, slaves);
}

std::string line_repaired(const Event&, const EventDescriber&) { return "line repaired: the ring is closed"; }

std::string link_down(const Event& e, const EventDescriber&) { return fmt::format("link {} down", role_name(e.a)); }
std::string link_up(const Event& e, const EventDescriber&) { return fmt::format("link {} up", role_name(e.a)); }

std::string bus_scan_status(const Event& e, const EventDescriber&) {
    return fmt::format("bus scan: {} slave(s) found, {} configured, {}", e.a, e.b, e.c != 0 ? "match" : "MISMATCH");
}

std::string bus_mismatch(const Event& e, const EventDescriber& describer) {
    return fmt::format("bus mismatch at position {} (configured there: {})", e.a + 1, describer.slave_at_position(e.a + 1));
}

std::string bus_mismatch_identification(const Event& e, const EventDescriber&) {
    return fmt::format("bus mismatch at position {}: identification 0x{:04x} expected {}, read {}", e.a, e.b, e.d,
                       e.c > 0xFFFF ? std::string("nothing") : fmt::format("{}", e.c));
}

std::string bus_mismatch_place(const Event& e, const EventDescriber&) {
    return fmt::format("bus mismatch at position {}: it hangs on station {} port {} (position {})", e.a, e.b,
                       static_cast<char>('A' + (e.c & 3)), e.d);
}

std::string slave_presence(const Event& e, const EventDescriber& describer) {
    return fmt::format("slave {} is {}", describer.slave(e.a),
                       e.b != 0 ? "present" : "absent (no answer at its station address)");
}

std::string slave_state_error(const Event& e, const EventDescriber& describer) {
    return fmt::format("slave {} is in {}, AL status code 0x{:04x} ({})", describer.slave(e.a),
                       wire::AlStatus{static_cast<std::uint8_t>(e.b)}.to_string(), e.c,
                       wire::al_status_code_text(static_cast<std::uint16_t>(e.c)));
}

std::string slave_identification_updated(const Event& e, const EventDescriber&) {
    return fmt::format("slave {}: AL status code 0x0061 (device identification value updated): its ID selector is its "
                       "station alias now ({}); re-initialised",
                       e.a, e.b);
}

std::string transition_failed(const Event& e, const EventDescriber& describer) {
    if (e.c == 0xFFFF) return fmt::format("transition {} -> {} failed", state_name(e.a), state_name(e.b));
    return fmt::format("transition {} -> {} failed at slave {}: the master stays in {}", state_name(e.a),
                       state_name(e.b), describer.slave(e.c), state_name(e.a));
}

std::string frame_response_error(const Event& e, const EventDescriber&) {
    std::string_view reason = "late or stale frame";
    if (e.a == static_cast<std::uint32_t>(FrameResponseReason::ForeignSourceMac)) reason = "foreign source MAC";
    if (e.a == static_cast<std::uint32_t>(FrameResponseReason::Malformed)) reason = "malformed frame";
    return fmt::format("frame response error on {}: {}", role_name(e.b), reason);
}
std::uint64_t frame_response_subject(const Event& e) { return pair_of(e.a, e.b); }  // the reason and the link

std::string topology_change_detected(const Event& e, const EventDescriber&) {
    return fmt::format("topology change: the AL status BRD counts {} slave(s), {} before", count_text(e.b),
                       count_text(e.a));
}

std::string cycle_stall(const Event& e, const EventDescriber&) {
    return fmt::format("{} cycle deadline(s) passed without a cycle (it woke {} µs after its deadline and ended that "
                       "much later): the machine did not run this master in time (other processes or the host), or "
                       "the cycle ran that long; the skipped cycles sent nothing",
                       e.b, e.a);
}

std::string coe_emergency(const Event& e, const EventDescriber& describer) {
    const auto code = static_cast<std::uint16_t>(e.b);
    return fmt::format("slave {}: CoE emergency 0x{:04x} ({}), error register 0x{:02x}, data {:02x} {:02x} {:02x} "
                       "{:02x} {:02x}",
                       describer.slave(e.a), code, wire::emergency_error_class(code), (e.b >> 16) & 0xFF, e.c & 0xFF,
                       (e.c >> 8) & 0xFF, (e.c >> 16) & 0xFF, e.c >> 24, e.d & 0xFF);
}
std::uint64_t one_subject(const Event&) { return 0; }
// A slave that sends the same emergency again and again (every poll) is one fault; another slave's, or another
// error code, is counted apart.
std::uint64_t coe_emergency_subject(const Event& e) { return pair_of(e.a, e.b & 0xFFFFu); }

}  // namespace

namespace events {

constinit const EventType kMasterStateChanged{"master-state-changed", master_state_changed};
constinit const EventType kCyclicWkcError{"cyclic-wkc-error", cyclic_wkc_error, {wkc_error_subject}};
constinit const EventType kFrameLost{"frame-lost", frame_lost, {frame_lost_subject}};
constinit const EventType kLineBreak{"line-break", line_break};
constinit const EventType kLineRepaired{"line-repaired", line_repaired};
constinit const EventType kLinkDown{"link-down", link_down};
constinit const EventType kLinkUp{"link-up", link_up};
constinit const EventType kBusScanStatus{"bus-scan-status", bus_scan_status};
constinit const EventType kBusMismatch{"bus-mismatch", bus_mismatch};
constinit const EventType kBusMismatchIdentification{"bus-mismatch-identification", bus_mismatch_identification};
constinit const EventType kBusMismatchPlace{"bus-mismatch-place", bus_mismatch_place};
constinit const EventType kSlavePresence{"slave-presence", slave_presence};
constinit const EventType kSlaveStateError{"slave-state-error", slave_state_error};
constinit const EventType kSlaveIdentificationUpdated{"slave-identification-updated", slave_identification_updated};
constinit const EventType kTransitionFailed{"transition-failed", transition_failed};
constinit const EventType kFrameResponseError{"frame-response-error", frame_response_error, {frame_response_subject}};
constinit const EventType kTopologyChangeDetected{"topology-change-detected", topology_change_detected};
constinit const EventType kCycleStall{"cycle-stall", cycle_stall, {one_subject}};
constinit const EventType kCoeEmergency{"coe-emergency", coe_emergency, {coe_emergency_subject}};

}  // namespace events

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

}  // namespace ecpair::master
