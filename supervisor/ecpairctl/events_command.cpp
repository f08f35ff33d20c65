// `ecpairctl events [--for SECONDS] [--json]`: the daemon's events as they
// happen (those since it started first), one line each.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "daemon_connection.hpp"
#include "ecpair/control/control_client.hpp"
#include "event_text.hpp"
#include "exit_codes.hpp"
#include "ctl_commands.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

int run_events_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    double seconds = 0;
    po::options_description options("ecpairctl events options");
    add_socket_options(options, sockets);
    options.add_options()
        ("for", po::value(&seconds), "stop after SECONDS (default: until interrupted)")
        ("json", "one JSON object per event and line");
    po::variables_map vm;
    const std::string usage = "ecpairctl events [--socket PATH] [--for SECONDS] [--json]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "events", usage, out, err)) return *rc;
    const bool json = vm.count("json") != 0;

    control::Request request;
    request.mutable_watch_events();
    bool refused = false;
    const auto socket = sockets.path();
    auto streamed = control::stream(
        socket, request,
        [&](const control::Response& r) {
            if (!r.ok()) {
                fmt::print(err, "ecpairctl: {}: {}\n", socket, r.error());
                refused = true;
                return false;
            }
            if (!r.has_event()) return true;
            if (json) {
                JsonWriter writer;
                write_event_json(writer, r.event());
                fmt::print(out, "{}\n", writer.str());
            } else {
                fmt::print(out, "{}\n", event_line(r.event()));
            }
            out.flush();
            return true;
        },
        std::chrono::milliseconds(static_cast<std::int64_t>(seconds * 1000)));
    if (!streamed) {
        const auto failure = describe_connection_failure(socket, streamed.error().message);
        fmt::print(err, "ecpairctl: {}\n", failure.message);
        return failure.exit_code;
    }
    return refused ? kExitRefused : kExitOk;
}

}  // namespace ecpair::ctl
