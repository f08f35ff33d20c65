// The supervisor's section: what this member is and why, its partner, its counters.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {

void supervisor_table(std::ostream& out, const control::StatusReply& s) {
    if (!s.redundancy().enabled() || !s.has_supervisor()) return;
    const auto& v = s.supervisor();
    fmt::print(out, "  supervisor: {}{} - {}\n", v.state(), v.forced_standby() ? " (FORCED STANDBY)" : "", v.why());
    if (!v.no_active().empty()) fmt::print(out, "  NO MASTER IS ACTIVE: {}\n", v.no_active());
    if (s.redundancy().red_state() == "ACTIVE") {
        fmt::print(out, "  partner {}: {}{}\n", v.partner().empty() ? "-" : v.partner(),
                   v.partner_standby().empty() ? "no answer" : v.partner_standby() + " standby",
                   v.partner_answer_age_ms() >= 0 ? fmt::format(", last answer {:.1f} ms ago", v.partner_answer_age_ms())
                                                  : std::string());
    } else {
        fmt::print(out, "  partner {}: last CMF {}, silence {:.1f} of {} ms (comm timeout)\n",
                   v.partner().empty() ? "-" : v.partner(),
                   v.last_cmf_age_ms() >= 0 ? fmt::format("{:.1f} ms ago", v.last_cmf_age_ms()) : std::string("never"),
                   v.silence_ms(), v.comm_timeout_ms());
    }
    if (v.handoff_cycle() != 0) fmt::print(out, "  hand-off at cycle {}\n", v.handoff_cycle());
    fmt::print(out, "  epoch {}, arbitration {}; takeovers {}, comm timeouts {}, collisions {} (backoffs won {}, lost {}), "
                    "hand-offs {} ({} cancelled), partner lost {}\n",
               v.epoch(), v.arbitration(), v.takeovers(), v.comm_timeouts(), v.collisions(), v.backoffs_won(),
               v.backoffs_lost(), v.handoffs(), v.handoffs_cancelled(), v.partner_lost());
}

void supervisor_json(JsonWriter& json, const control::StatusReply& s) {
    json.key("supervisor");
    if (!s.has_supervisor()) {
        json.null();
        return;
    }
    const auto& v = s.supervisor();
    auto text_or_null = [&json](const std::string& text) {
        if (text.empty()) {
            json.null();
        } else {
            json.value(text);
        }
    };
    auto age_or_null = [&json](double ms) {
        if (ms < 0) {
            json.null();
        } else {
            json.value(ms);
        }
    };
    json.begin_object().key("state").value(v.state()).key("why").value(v.why());
    json.key("forced_standby").value(v.forced_standby()).key("epoch").value(v.epoch());
    json.key("arbitration").value(v.arbitration()).key("comm_timeout_ms").value(v.comm_timeout_ms());
    json.key("silence_ms").value(v.silence_ms());
    json.key("last_cmf_age_ms");
    age_or_null(v.last_cmf_age_ms());
    json.key("partner_answer_age_ms");
    age_or_null(v.partner_answer_age_ms());
    json.key("partner");
    text_or_null(v.partner());
    json.key("partner_standby");
    text_or_null(v.partner_standby());
    json.key("handoff_cycle").value(v.handoff_cycle());
    json.key("no_active");
    text_or_null(v.no_active());
    json.key("takeovers").value(v.takeovers()).key("comm_timeouts").value(v.comm_timeouts());
    json.key("collisions").value(v.collisions()).key("backoffs_won").value(v.backoffs_won());
    json.key("backoffs_lost").value(v.backoffs_lost()).key("handoffs").value(v.handoffs());
    json.key("handoffs_cancelled").value(v.handoffs_cancelled()).key("partner_lost").value(v.partner_lost());
    json.end_object();
}

}  // namespace ecpair::ctl
