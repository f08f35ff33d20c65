// The Hot-Connect section of `ecpairctl status`: one line of the summary
// (`ecpairctl groups` has the groups themselves).

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "hot_connect_view.hpp"
#include "status_sections.hpp"

namespace ecpair::ctl {

void hot_connect_table(std::ostream& out, const control::StatusReply& s) {
    if (!s.has_hot_connect()) return;  // an older daemon
    const auto& h = s.hot_connect();
    if (h.groups() == 0 && h.changes() == 0 && h.mismatches() == 0) return;  // an ENI without groups, nothing happened
    fmt::print(out, "  hot-connect: {}, mode {}{}; {} of {} optional group(s) present, {} slave(s) on the bus; {} change(s){}{}\n",
               h.state(), h.mode(), h.border_close() ? ", border close" : "", h.groups_present(), h.groups(),
               h.slaves_on_bus(), h.changes(),
               h.last_result().empty() ? std::string() : fmt::format(", the last: {}", h.last_result()),
               h.mismatches() == 0 ? std::string() : fmt::format("; {} MISMATCH(ES) (ecpairctl groups)", h.mismatches()));
}

void hot_connect_json(JsonWriter& json, const control::StatusReply& s) {
    json.key("hot_connect");
    if (!s.has_hot_connect()) {
        json.null();
        return;
    }
    json.begin_object();
    write_hot_connect_summary_json(json, s.hot_connect());
    json.end_object();
}

}  // namespace ecpair::ctl
