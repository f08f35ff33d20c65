#pragma once
// The pair at a glance, from both members' status: one column per member
// (role, master state, partner, mirror, links, ring, cycles, link guard,
// slaves in OP) and a verdict line on the pair as a whole: who is ACTIVE,
// whether the other is a hot standby, two ACTIVE or none, a member that
// cannot be reached.

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/control.pb.h"
#include "json_writer.hpp"

namespace ecpair::ctl {

struct PairMember {
    std::string socket;
    std::optional<control::StatusReply> status;  // nullopt: not reachable
    std::string error;                           // why not
    int exit_code = 0;                           // and the exit code that failure gives (exit_codes.hpp)
};

// The verdict line ("m1 ACTIVE; m2 INACTIVE, hot standby (mirrored cycle 123)").
std::string pair_verdict(const std::vector<PairMember>& members);

void print_pair_table(std::ostream& out, const std::vector<PairMember>& members);
void write_pair_json(JsonWriter& json, const std::vector<PairMember>& members);

}  // namespace ecpair::ctl
