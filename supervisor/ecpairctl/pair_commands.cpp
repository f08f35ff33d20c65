// `ecpairctl switchover`, `force-standby` and `unforce-standby`: one request
// each to a pair member's supervisor.

#include <ostream>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"

namespace ecpair::ctl {
int run_switchover_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_socket_only_request(args, out, err, "switchover", [](control::Request& r) { r.mutable_switchover(); },
                                   "switchover started: watch the events for the hand-off (or `ecpairctl status`)");
}

int run_force_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_socket_only_request(args, out, err, "force-standby",
                                   [](control::Request& r) { r.mutable_force_standby()->set_forced(true); },
                                   "forced to standby: this member will not become ACTIVE (an ACTIVE one hands over first)");
}

int run_unforce_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_socket_only_request(args, out, err, "unforce-standby",
                                   [](control::Request& r) { r.mutable_force_standby()->set_forced(false); },
                                   "standby no longer forced");
}

}  // namespace ecpair::ctl
