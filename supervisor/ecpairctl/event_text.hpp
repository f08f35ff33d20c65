#pragma once
// One event of the operator API as ecpairctl prints it: a line for people
// ("20:18:50.432 link-guard-links-down cycle 962: link guard took ...",
// "20:18:51.000 cyclic-wkc-error (summary) cycle 1962: 1000 more ...") or a
// JSON object for scripts (with repeat, count, total and the cycles for a
// summary or an end).

#include <string>

#include "ecpair/control.pb.h"
#include "json_writer.hpp"

namespace ecpair::ctl {

std::string local_time_of(std::int64_t unix_time_ms);  // "HH:MM:SS.mmm"
std::string event_line(const control::EventMessage& event);
void write_event_json(JsonWriter& json, const control::EventMessage& event);

}  // namespace ecpair::ctl
