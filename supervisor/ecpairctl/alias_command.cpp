// `ecpairctl alias set STATION VALUE`: programs a slave's configured station
// alias into its SII (word 4, the checksum in word 7 rewritten); the slave
// takes it over at its next power-on (hot-connect.md §9).

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

int run_alias_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    std::string verb;
    std::uint32_t station = 0;
    std::string value_text;
    po::options_description options("ecpairctl alias options");
    add_socket_options(options, sockets);
    options.add_options()
        ("verb", po::value(&verb)->required(), "set")
        ("station", po::value(&station)->required(), "the slave's station address")
        ("value", po::value(&value_text)->required(), "the alias, decimal or 0x hex");
    po::positional_options_description positional;
    positional.add("verb", 1).add("station", 1).add("value", 1);
    po::variables_map vm;
    const std::string usage = "ecpairctl alias [--socket PATH] set STATION VALUE";
    if (auto rc = parse_arguments(args, options, &positional, vm, "alias", usage, out, err)) return *rc;
    if (verb != "set") {
        fmt::print(err, "ecpairctl alias: '{}' is not 'set' (usage: {})\n", verb, usage);
        return kExitUsage;
    }
    std::size_t used = 0;
    unsigned long value = 0;
    try {
        value = std::stoul(value_text, &used, 0);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != value_text.size() || value > 0xFFFF || value_text.front() == '-') {
        fmt::print(err, "ecpairctl alias: VALUE must be 0..65535 (decimal or 0x hex), got '{}' (usage: {})\n", value_text,
                   usage);
        return kExitUsage;
    }
    control::Request request;
    request.mutable_hc_set_alias()->set_station(station);
    request.mutable_hc_set_alias()->set_alias(static_cast<std::uint32_t>(value));
    auto response = call_daemon(sockets.path(), request, err);
    if (!response) return response.error();
    fmt::print(out, "station {}: SII station alias {} (was {}); the slave takes it over at its next power-on\n", station,
               value, response->hc_alias().previous());
    return kExitOk;
}

}  // namespace ecpair::ctl
