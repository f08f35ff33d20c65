// The master's own sections: summary (who, master state, role), links and
// ring, cycles and frames.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {
namespace {

std::string up_down(bool up) { return up ? "up" : "DOWN"; }

}  // namespace

bool forced_standby(const control::StatusReply& s) { return s.supervisor().forced_standby(); }

void summary_table(std::ostream& out, const control::StatusReply& s) {
    fmt::print(out, "{}: master {} (target {}), cycle {} µs\n", s.name(), s.master_state(), s.target_state(),
               s.cycle_time_us());
    if (!s.sequence_error().empty()) fmt::print(out, "  state machine stopped: {}\n", s.sequence_error());
}

void summary_json(JsonWriter& json, const control::StatusReply& s) {
    json.key("name").value(s.name());
    json.key("master_state").value(s.master_state());
    json.key("target_state").value(s.target_state());
    json.key("red_state");
    if (s.redundancy().enabled()) {
        json.value(s.redundancy().red_state());
    } else {
        json.null();  // not a member of a pair
    }
    json.key("partner_seen").value(s.redundancy().enabled() && s.redundancy().partner_seen());
    json.key("forced_standby").value(forced_standby(s));
    json.key("cycle_time_us").value(s.cycle_time_us());
    json.key("sequence_error");
    if (s.sequence_error().empty()) {
        json.null();
    } else {
        json.value(s.sequence_error());
    }
}

void links_table(std::ostream& out, const control::StatusReply& s) {
    fmt::print(out, "  links: MAIN {}, RED {}; ring {}{}\n", up_down(s.main_link_up()), up_down(s.red_link_up()),
               s.ring_state(),
               s.ring_state() == "broken" && s.reachable_from_main() > 0
                   ? fmt::format(" after slave {}", s.reachable_from_main())
                   : std::string());
}

void links_json(JsonWriter& json, const control::StatusReply& s) {
    json.key("links").begin_object().key("main").value(s.main_link_up()).key("red").value(s.red_link_up()).end_object();
    json.key("ring").begin_object().key("state").value(s.ring_state());
    json.key("reachable_from_main").value(s.reachable_from_main()).end_object();
}

void cycles_table(std::ostream& out, const control::StatusReply& s) {
    const auto& t = s.timing();
    fmt::print(out, "  cycles {} ({} late, {} skipped; wake-up latency p50 {:.0f} µs, p99 {:.0f} µs, max {:.0f} µs{})\n",
               t.cycles(), t.late(), t.skipped(), t.wake_latency_p50_us(), t.wake_latency_p99_us(),
               t.wake_latency_max_us(), t.realtime() ? ", SCHED_FIFO" : "");
    const auto& c = s.counters();
    fmt::print(out,
               "  frames sent {}, lost {}, late copies {} (on MAIN {}, on RED {}), incomplete cycles {}, WKC errors {}, "
               "foreign {}\n",
               c.frames_sent(), c.frames_lost(), c.late_copies(), c.late_copies() - c.late_copies_on_red(),
               c.late_copies_on_red(), c.cycles_incomplete(), c.wkc_errors(), c.foreign_frames());
}

void cycles_json(JsonWriter& json, const control::StatusReply& s) {
    const auto& t = s.timing();
    json.key("cycles").begin_object();
    json.key("count").value(t.cycles()).key("late").value(t.late()).key("skipped").value(t.skipped());
    json.key("wake_latency_p50_us").value(t.wake_latency_p50_us());
    json.key("wake_latency_p99_us").value(t.wake_latency_p99_us());
    json.key("wake_latency_max_us").value(t.wake_latency_max_us());
    json.key("realtime").value(t.realtime()).end_object();
    const auto& c = s.counters();
    json.key("frames").begin_object();
    json.key("sent").value(c.frames_sent()).key("lost").value(c.frames_lost()).key("late_copies").value(c.late_copies());
    json.key("late_copies_on_red").value(c.late_copies_on_red());
    json.key("incomplete_cycles").value(c.cycles_incomplete()).key("wkc_errors").value(c.wkc_errors());
    json.key("foreign").value(c.foreign_frames()).key("send_errors").value(c.send_errors()).end_object();
}

}  // namespace ecpair::ctl
