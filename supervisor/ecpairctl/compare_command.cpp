// `ecpairctl compare --socket A --socket B`: the two members' image
// histories compared cycle by cycle (control/image_history_comparison.hpp;
// exit 1 when a cycle differs, both members sent in one, or none was compared).

#include <array>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "ecpair/control/image_history_comparison.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

int run_compare_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    po::options_description options("ecpairctl compare options");
    add_socket_options(options, sockets);
    po::variables_map vm;
    const std::string usage = "ecpairctl compare --socket A --socket B";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "compare", usage, out, err)) return *rc;
    if (sockets.sockets.size() != 2) {
        fmt::print(err, "ecpairctl compare: give exactly two --socket (usage: {})\n", usage);
        return kExitUsage;
    }
    std::array<control::ImageHistoryReply, 2> histories;
    for (std::size_t i = 0; i < 2; ++i) {
        control::Request request;
        request.mutable_image_history();
        auto response = call_daemon(sockets.sockets[i], request, err);
        if (!response) return response.error();
        histories[i] = response->image_history();
    }
    const auto comparison = control::compare_image_histories(histories[0], histories[1]);
    fmt::print(out, "{}\n", comparison.describe());
    return comparison.mirrored() ? kExitOk : kExitRefused;
}

}  // namespace ecpair::ctl
