// `ecpairctl compare --socket A --socket B`: the two members' image
// histories compared cycle by cycle (exit 1 when any SAFEOP/OP cycle differs
// or none is in both).

#include <array>
#include <map>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
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
    std::array<std::map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>>, 2> histories;
    for (std::size_t i = 0; i < 2; ++i) {
        control::Request request;
        request.mutable_image_history();
        auto response = call_daemon(sockets.sockets[i], request, err);
        if (!response) return response.error();
        // Only SAFEOP and OP carry outputs on the wire: before, nothing can be mirrored.
        for (const auto& e : response->image_history().entries()) {
            if (e.master_state() == "SAFEOP" || e.master_state() == "OP") {
                histories[i][e.cycle()] = {e.inputs_crc(), e.outputs_crc()};
            }
        }
    }
    std::size_t common = 0;
    std::size_t differ = 0;
    for (const auto& [cycle, crcs] : histories[0]) {
        const auto it = histories[1].find(cycle);
        if (it == histories[1].end()) continue;
        ++common;
        if (it->second != crcs) ++differ;
    }
    fmt::print(out, "{} cycles recorded by both: {} with equal inputs and outputs, {} differ\n", common, common - differ,
               differ);
    return common > 0 && differ == 0 ? kExitOk : kExitRefused;
}

}  // namespace ecpair::ctl
