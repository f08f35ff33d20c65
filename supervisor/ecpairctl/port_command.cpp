// `ecpairctl port STATION PORT SETTING`: a slave port's loop setting (ESC
// register 0x0101): auto, auto-close, open or closed (hot-connect.md §5).

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

int run_port_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    std::uint32_t station = 0;
    std::string port;
    std::string setting;
    po::options_description options("ecpairctl port options");
    add_socket_options(options, sockets);
    options.add_options()
        ("station", po::value(&station)->required(), "the slave's station address")
        ("port", po::value(&port)->required(), "B, C or D")
        ("setting", po::value(&setting)->required(), "auto, auto-close, open or closed");
    po::positional_options_description positional;
    positional.add("station", 1).add("port", 1).add("setting", 1);
    po::variables_map vm;
    const std::string usage = "ecpairctl port [--socket PATH] STATION B|C|D auto|auto-close|open|closed";
    if (auto rc = parse_arguments(args, options, &positional, vm, "port", usage, out, err)) return *rc;
    control::Request request;
    auto* p = request.mutable_hc_set_port();
    p->set_station(station);
    p->set_port(port);
    p->set_setting(setting);
    if (auto response = call_daemon(sockets.path(), request, err); !response) return response.error();
    fmt::print(out, "station {} port {}: {}\n", station, port, setting);
    return kExitOk;
}

}  // namespace ecpair::ctl
