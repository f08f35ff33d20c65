// The operations sections: the link guard, the demo's loopback check, the
// operator socket itself.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {

void link_guard_table(std::ostream& out, const control::StatusReply& s) {
    const auto& g = s.link_guard();
    if (!g.enabled()) return;
    fmt::print(out, "  link guard: {}, {}; links down after {} ms standing still; taken down {} time(s); longest heartbeat gap {:.1f} ms\n",
               g.running() ? "running" : "NOT RUNNING (links unguarded)",
               g.links_down() ? "LINKS DOWN (until this member may drive them)" : "links up", g.hang_timeout_ms(),
               g.links_taken_down(), g.max_heartbeat_gap_ms());
    if (!g.last_action().empty()) fmt::print(out, "  link guard last took {}\n", g.last_action());
}

void link_guard_json(JsonWriter& json, const control::StatusReply& s) {
    const auto& g = s.link_guard();
    json.key("link_guard").begin_object().key("enabled").value(g.enabled());
    if (g.enabled()) {
        json.key("running").value(g.running()).key("links_down").value(g.links_down());
        json.key("hang_timeout_ms").value(g.hang_timeout_ms()).key("links_taken_down").value(g.links_taken_down());
        json.key("links_brought_up").value(g.links_brought_up());
        json.key("max_heartbeat_gap_ms").value(g.max_heartbeat_gap_ms());
        json.key("last_action");
        if (g.last_action().empty()) {
            json.null();
        } else {
            json.value(g.last_action());
        }
    }
    json.end_object();
}

void loopback_table(std::ostream& out, const control::StatusReply& s) {
    if (s.loopback().cycles_checked() == 0) return;
    fmt::print(out, "  loopback check: {} cycles, {} slave checks, {} mismatches\n", s.loopback().cycles_checked(),
               s.loopback().slave_checks(), s.loopback().mismatches());
}

void loopback_json(JsonWriter& json, const control::StatusReply& s) {
    const auto& l = s.loopback();
    json.key("loopback").begin_object().key("cycles_checked").value(l.cycles_checked());
    json.key("slave_checks").value(l.slave_checks()).key("mismatches").value(l.mismatches()).end_object();
}

void operator_socket_table(std::ostream& out, const control::StatusReply& s) {
    const auto& o = s.operator_socket();
    if (o.max_clients() == 0) return;  // an older daemon
    fmt::print(out, "  operator socket: {} client(s) of {}; closed: {} timed out, {} busy, {} malformed, {} slow watchers\n",
               o.clients(), o.max_clients(), o.timed_out(), o.refused_busy(), o.malformed(), o.slow_watchers());
}

void operator_socket_json(JsonWriter& json, const control::StatusReply& s) {
    const auto& o = s.operator_socket();
    json.key("operator_socket").begin_object().key("clients").value(o.clients()).key("max_clients").value(o.max_clients());
    json.key("request_timeout_ms").value(o.request_timeout_ms()).key("timed_out").value(o.timed_out());
    json.key("refused_busy").value(o.refused_busy()).key("malformed").value(o.malformed());
    json.key("slow_watchers").value(o.slow_watchers()).end_object();
}

}  // namespace ecpair::ctl
