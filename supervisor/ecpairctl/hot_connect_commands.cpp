// The Hot-Connect operations of hot-connect.md §5 that need no more than a
// socket: `ecpairctl accept`, `topology-change`, `block-node` and
// `open-blocked-ports`. A refusal prints the daemon's error, which starts
// with its code (InvalidState, InvalidParam, SlaveNotPresent, NotFound,
// MasterRedStateInactive), and exits 1.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

int run_accept_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_socket_only_request(args, out, err, "accept", [](control::Request& r) { r.mutable_hc_accept(); },
                                   "accepted: the new groups go to the master state");
}

int run_topology_change_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    return run_socket_only_request(args, out, err, "topology-change", [](control::Request& r) { r.mutable_hc_force(); },
                                   "topology change started: watch the events for topology-change-done");
}

int run_block_node_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    std::uint32_t mismatch = 0;
    std::uint32_t station = 0;
    po::options_description options("ecpairctl block-node options");
    add_socket_options(options, sockets);
    options.add_options()
        ("mismatch", po::value(&mismatch), "the mismatch, as `ecpairctl groups` numbers them (default: the first)")
        ("station", po::value(&station), "or: the slave whose upstream port to close");
    po::variables_map vm;
    const std::string usage = "ecpairctl block-node [--mismatch N | --station S] [--socket PATH]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "block-node", usage, out, err)) return *rc;
    if (vm.count("mismatch") != 0 && vm.count("station") != 0) {
        fmt::print(err, "ecpairctl block-node: give --mismatch or --station, not both (usage: {})\n", usage);
        return kExitUsage;
    }
    control::Request request;
    auto* b = request.mutable_hc_block_node();
    if (vm.count("mismatch") != 0) b->set_mismatch(mismatch);
    if (vm.count("station") != 0) b->set_station(station);
    auto response = call_daemon(sockets.path(), request, err);
    if (!response) return response.error();
    for (const auto& p : response->hc_ports().ports()) {
        fmt::print(out, "station {} port {} closed: what hangs behind it is cut off\n", p.station(), p.port());
    }
    return kExitOk;
}

int run_open_blocked_ports_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    po::options_description options("ecpairctl open-blocked-ports options");
    add_socket_options(options, sockets);
    po::variables_map vm;
    const std::string usage = "ecpairctl open-blocked-ports [--socket PATH]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "open-blocked-ports", usage, out, err)) return *rc;
    control::Request request;
    request.mutable_hc_open_blocked_ports();
    auto response = call_daemon(sockets.path(), request, err);
    if (!response) return response.error();
    if (response->hc_ports().ports().empty()) fmt::print(out, "no port was blocked\n");
    for (const auto& p : response->hc_ports().ports()) {
        fmt::print(out, "station {} port {} open again\n", p.station(), p.port());
    }
    return kExitOk;
}

}  // namespace ecpair::ctl
