// `ecpairctl switchover`, `force-standby` and `unforce-standby`: one request
// each to a pair member's supervisor.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {
namespace {

namespace po = boost::program_options;

int run_pair_request(const CommandArgs& args, std::ostream& out, std::ostream& err, const char* command,
                     void (*fill)(control::Request&), const char* done) {
    SocketOptions sockets;
    po::options_description options("ecpairctl options");
    add_socket_options(options, sockets);
    po::variables_map vm;
    const std::string usage = fmt::format("ecpairctl {} [--socket PATH]", command);
    if (auto rc = parse_arguments(args, options, nullptr, vm, command, usage, out, err)) return *rc;
    control::Request request;
    fill(request);
    if (auto response = call_daemon(sockets.path(), request, err); !response) return response.error();
    fmt::print(out, "{}\n", done);
    return kExitOk;
}

}  // namespace

int run_switchover_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_pair_request(args, out, err, "switchover", [](control::Request& r) { r.mutable_switchover(); },
                            "switchover started: watch the events for the hand-off (or `ecpairctl status`)");
}

int run_force_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_pair_request(args, out, err, "force-standby",
                            [](control::Request& r) { r.mutable_force_standby()->set_forced(true); },
                            "forced to standby: this member will not become ACTIVE (an ACTIVE one hands over first)");
}

int run_unforce_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_pair_request(args, out, err, "unforce-standby",
                            [](control::Request& r) { r.mutable_force_standby()->set_forced(false); },
                            "standby no longer forced");
}

}  // namespace ecpair::ctl
