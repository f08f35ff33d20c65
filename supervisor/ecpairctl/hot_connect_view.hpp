#pragma once
// How ecpairctl shows Hot-Connect (hot-connect.md §5): the groups with their
// members and presence, the mismatch descriptors and the blocked ports, as a
// table and as JSON (groups_command.cpp), and the summary line of
// `ecpairctl status` (status_section_hot_connect.cpp).

#include <iosfwd>

#include "ecpair/control.pb.h"
#include "json_writer.hpp"

namespace ecpair::ctl {

void print_hot_connect_groups(std::ostream& out, const control::HotConnectGroupsReply& reply);
void write_hot_connect_groups_json(JsonWriter& json, const control::HotConnectGroupsReply& reply);

// The keys of a HotConnectSummary into an open JSON object.
void write_hot_connect_summary_json(JsonWriter& json, const control::HotConnectSummary& summary);

}  // namespace ecpair::ctl
