// The pair member's section: role, partner, mirror, master process data,
// store-and-forward counters.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {
namespace {

std::string hex(const std::string& bytes) {
    std::string text;
    for (const char byte : bytes.substr(0, 16)) text += fmt::format("{:02x}", static_cast<unsigned char>(byte));
    return text.empty() ? std::string("-") : text;
}

}  // namespace

void redundancy_table(std::ostream& out, const control::StatusReply& s) {
    if (!s.redundancy().enabled()) return;
    const auto& r = s.redundancy();
    fmt::print(out, "  redundancy: {}, partner {}{}{}\n", r.red_state(), r.partner_seen() ? "seen" : "NOT seen",
               r.red_state() == "INACTIVE" ? fmt::format(", mirrored cycle {}", r.mirrored_cycle()) : std::string(),
               forced_standby(s) ? ", FORCED STANDBY" : "");
    if (!r.partner_mismatch().empty()) fmt::print(out, "  partner differs (cold standby): {}\n", r.partner_mismatch());
    fmt::print(out, "  master PD out {} in {}\n", hex(r.master_pd_out()), hex(r.master_pd_in()));
    if (r.red_state() == "INACTIVE") {
        fmt::print(out, "  store-and-forward ({}): {} to MAIN, {} to RED, {} bounced, dropped: {} circulating, {} non-EtherCAT, {} damaged\n",
                   r.forwarding_path(), r.forwarded_main(), r.forwarded_red(), r.bounced(), r.dropped_circulating(),
                   r.dropped_non_ethercat(),
                   r.dropped_damaged());
    }
}

void redundancy_json(JsonWriter& json, const control::StatusReply& s) {
    const auto& r = s.redundancy();
    json.key("redundancy").begin_object().key("enabled").value(r.enabled());
    if (r.enabled()) {
        json.key("partner_mismatch");
        if (r.partner_mismatch().empty()) {
            json.null();
        } else {
            json.value(r.partner_mismatch());
        }
        json.key("mirrored_cycle").value(r.mirrored_cycle());
        json.key("master_pd_out").value(hex(r.master_pd_out())).key("master_pd_in").value(hex(r.master_pd_in()));
        json.key("forwarded_main").value(r.forwarded_main()).key("forwarded_red").value(r.forwarded_red());
        json.key("bounced").value(r.bounced()).key("dropped_circulating").value(r.dropped_circulating());
        json.key("dropped_non_ethercat").value(r.dropped_non_ethercat()).key("dropped_damaged").value(r.dropped_damaged());
        json.key("forwarding_path").value(r.forwarding_path());
    }
    json.end_object();
}

}  // namespace ecpair::ctl
