#include "status_sections.hpp"

#include <array>

#include "tap_bridge_status.hpp"

namespace ecpair::ctl {

std::span<const StatusSection> status_sections() {
    static constexpr std::array kSections{
        StatusSection{"summary", summary_table, summary_json},
        StatusSection{"links", links_table, links_json},
        StatusSection{"cycles", cycles_table, cycles_json},
        StatusSection{"redundancy", redundancy_table, redundancy_json},
        StatusSection{"supervisor", supervisor_table, supervisor_json},
        StatusSection{"link_guard", link_guard_table, link_guard_json},
        StatusSection{"tap_bridge", print_tap_bridge_status, write_tap_bridge_json},
        StatusSection{"loopback", loopback_table, loopback_json},
        StatusSection{"operator_socket", operator_socket_table, operator_socket_json},
        StatusSection{"slaves", slaves_table, slaves_json},
    };
    return kSections;
}

void print_status_table(std::ostream& out, const control::StatusReply& status) {
    for (const auto& section : status_sections()) section.table(out, status);
}

void write_status_json(JsonWriter& json, const control::StatusReply& status) {
    json.begin_object();
    for (const auto& section : status_sections()) section.json(json, status);
    json.end_object();
}

}  // namespace ecpair::ctl
