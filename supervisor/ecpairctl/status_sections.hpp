#pragma once
// `ecpairctl status` is made of sections, each printing its part of a
// StatusReply as lines of the table and as keys of the --json object. The
// order is the list in status_sections.cpp; a new part of the status (a TAP
// bridge, Hot-Connect groups, the supervisor) is a new section: one file
// with its two functions and one line in that list.

#include <iosfwd>
#include <span>
#include <string_view>

#include "ecpair/control.pb.h"
#include "json_writer.hpp"

namespace ecpair::ctl {

struct StatusSection {
    std::string_view name;
    // Lines of the table (nothing when the section has nothing to say).
    void (*table)(std::ostream& out, const control::StatusReply& status);
    // Keys into the open top-level JSON object.
    void (*json)(JsonWriter& json, const control::StatusReply& status);
};

std::span<const StatusSection> status_sections();

void print_status_table(std::ostream& out, const control::StatusReply& status);
// One JSON object of every section.
void write_status_json(JsonWriter& json, const control::StatusReply& status);

// The sections (status_section_*.cpp).
void summary_table(std::ostream& out, const control::StatusReply& s);
void summary_json(JsonWriter& json, const control::StatusReply& s);
void links_table(std::ostream& out, const control::StatusReply& s);
void links_json(JsonWriter& json, const control::StatusReply& s);
void cycles_table(std::ostream& out, const control::StatusReply& s);
void cycles_json(JsonWriter& json, const control::StatusReply& s);
void redundancy_table(std::ostream& out, const control::StatusReply& s);
void redundancy_json(JsonWriter& json, const control::StatusReply& s);
void supervisor_table(std::ostream& out, const control::StatusReply& s);
void supervisor_json(JsonWriter& json, const control::StatusReply& s);
void link_guard_table(std::ostream& out, const control::StatusReply& s);
void link_guard_json(JsonWriter& json, const control::StatusReply& s);
void loopback_table(std::ostream& out, const control::StatusReply& s);
void loopback_json(JsonWriter& json, const control::StatusReply& s);
void operator_socket_table(std::ostream& out, const control::StatusReply& s);
void operator_socket_json(JsonWriter& json, const control::StatusReply& s);
void slaves_table(std::ostream& out, const control::StatusReply& s);
void slaves_json(JsonWriter& json, const control::StatusReply& s);

// Whether the member is in forced standby (the Supervisor's status).
bool forced_standby(const control::StatusReply& s);

}  // namespace ecpair::ctl
