#pragma once
// ecpairctl commands that talk to a running ecpaird over its operator socket:
//   status [--variables N]   a readable table of the daemon's state
//   events [--for SECONDS]   the event stream (watch)
//   state STATE              ask for INIT, PREOP, SAFEOP or OP
//   red-state STATE          make this controller ACTIVE or INACTIVE (redundant pair, no hand-off)
//   switchover               a zero-loss hand-off to the partner (asked on either member)
//   force-standby / unforce-standby  keep this member from becoming ACTIVE, or release it
//   compare --socket A --socket B
//                            compare two pair members' image histories cycle by
//                            cycle (exit 1 when any SAFEOP/OP cycle differs)
// Every command takes --socket PATH (default /run/ecpair/<--name>.sock,
// --name defaulting to "ecpaird").
//
// Exit codes: 0 done, 1 the daemon refused the request, 2 bad arguments,
// 3 the daemon cannot be reached.

#include <iosfwd>
#include <string>
#include <vector>

namespace ecpair::ctl {

int run_status_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int run_events_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int run_state_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int run_compare_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int run_red_state_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
enum class PairCommand { Switchover, ForceStandby, UnforceStandby };
int run_pair_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, PairCommand command);

}  // namespace ecpair::ctl
