// `ecpairctl state STATE` and `ecpairctl red-state ACTIVE|INACTIVE`: one
// request each, differing only in what they ask for.

#include <functional>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {
namespace {

namespace po = boost::program_options;

int run_state_request(const CommandArgs& args, std::ostream& out, std::ostream& err, const char* command,
                      const char* usage, const char* values,
                      const std::function<void(control::Request&, const std::string&)>& fill) {
    SocketOptions sockets;
    std::string state;
    po::options_description options("ecpairctl options");
    add_socket_options(options, sockets);
    options.add_options()("state", po::value(&state)->required(), values);
    po::positional_options_description positional;
    positional.add("state", 1);
    po::variables_map vm;
    if (auto rc = parse_arguments(args, options, &positional, vm, command, usage, out, err)) return *rc;

    control::Request request;
    fill(request, state);
    if (auto response = call_daemon(sockets.path(), request, err); !response) return response.error();
    fmt::print(out, "{} requested\n", state);
    return kExitOk;
}

}  // namespace

int run_state_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_state_request(args, out, err, "state", "ecpairctl state [--socket PATH] STATE", "INIT, PREOP, SAFEOP or OP",
                             [](control::Request& r, const std::string& s) { r.mutable_set_master_state()->set_state(s); });
}

int run_red_state_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_state_request(args, out, err, "red-state", "ecpairctl red-state [--socket PATH] ACTIVE|INACTIVE",
                             "ACTIVE or INACTIVE",
                             [](control::Request& r, const std::string& s) { r.mutable_set_red_state()->set_state(s); });
}

}  // namespace ecpair::ctl
