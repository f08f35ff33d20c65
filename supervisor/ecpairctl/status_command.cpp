#include "status_command.hpp"

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "exit_codes.hpp"
#include "status_sections.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

std::vector<PairMember> fetch_members(const std::vector<std::string>& sockets, std::uint32_t variables) {
    std::vector<PairMember> members;
    for (const auto& socket : sockets) {
        control::Request request;
        request.mutable_status()->set_max_variables(variables);
        PairMember member{socket, std::nullopt, {}, kExitOk};
        if (auto response = ask_daemon(socket, request)) {
            member.status = response->status();
        } else {
            member.error = response.error().message;
            member.exit_code = response.error().exit_code;
        }
        members.push_back(std::move(member));
    }
    return members;
}

int run_status_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    std::uint32_t variables = 0;
    po::options_description options("ecpairctl status options");
    add_socket_options(options, sockets);
    options.add_options()
        ("json", "one JSON object instead of the table")
        ("variables", po::value(&variables), "show the first N input and output variables");
    po::variables_map vm;
    const std::string usage = "ecpairctl status [--socket PATH [--socket PATH]] [--json] [--variables N]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "status", usage, out, err)) return *rc;
    const auto paths = sockets.paths();
    if (paths.size() > 2) {
        fmt::print(err, "ecpairctl status: give one --socket, or two for the pair view (got {})\n", paths.size());
        return kExitUsage;
    }
    const bool json = vm.count("json") != 0;

    if (paths.size() == 1) {
        control::Request request;
        request.mutable_status()->set_max_variables(variables);
        auto response = call_daemon(paths[0], request, err);
        if (!response) return response.error();
        if (json) {
            JsonWriter writer;
            write_status_json(writer, response->status());
            fmt::print(out, "{}\n", writer.str());
        } else {
            print_status_table(out, response->status());
        }
        return kExitOk;
    }

    const auto members = fetch_members(paths, variables);
    if (json) {
        JsonWriter writer;
        write_pair_json(writer, members);
        fmt::print(out, "{}\n", writer.str());
    } else {
        print_pair_table(out, members);
    }
    int rc = kExitOk;
    for (const auto& m : members) {
        if (m.status) continue;
        fmt::print(err, "ecpairctl: {}\n", m.error);
        if (rc == kExitOk) rc = m.exit_code;
    }
    return rc;
}

}  // namespace ecpair::ctl
