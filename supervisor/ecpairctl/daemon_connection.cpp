#include "daemon_connection.hpp"

#include <grp.h>
#include <sys/stat.h>

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ecpair/control/control_client.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

std::vector<std::string> SocketOptions::paths() const {
    if (!sockets.empty()) return sockets;
    return {fmt::format("/run/ecpair/{}.sock", name)};
}

void add_socket_options(po::options_description& options, SocketOptions& sockets) {
    options.add_options()
        ("help,h", "this text")
        ("socket,s", po::value(&sockets.sockets)->composing(), "operator socket of the daemon")
        ("name,n", po::value(&sockets.name), "daemon name: the socket is /run/ecpair/NAME.sock (default ecpaird)");
}

std::optional<int> parse_arguments(const std::vector<std::string>& args, const po::options_description& options,
                                   const po::positional_options_description* positional, po::variables_map& vm,
                                   const std::string& command, const std::string& usage, std::ostream& out,
                                   std::ostream& err) {
    try {
        auto parser = po::command_line_parser(args).options(options);
        if (positional) parser.positional(*positional);
        po::store(parser.run(), vm);
        if (vm.count("help") != 0) {
            fmt::print(out, "usage: {}\n{}", usage, fmt::streamed(options));
            return kExitOk;
        }
        po::notify(vm);
    } catch (const po::error& e) {
        fmt::print(err, "ecpairctl {}: {} (usage: {})\n", command, e.what(), usage);
        return kExitUsage;
    }
    return std::nullopt;
}

DaemonFailure describe_connection_failure(const std::string& socket, const std::string& client_error) {
    struct stat info {};
    const bool exists = ::stat(socket.c_str(), &info) == 0;
    if (client_error.find("Permission denied") != std::string::npos && exists) {
        const group* g = ::getgrgid(info.st_gid);
        return {fmt::format("{}: permission denied: the socket is mode {:o}, group {}; run as root or as a member of {}",
                            socket, info.st_mode & 0777, g ? g->gr_name : std::to_string(info.st_gid),
                            g ? g->gr_name : std::to_string(info.st_gid)),
                kExitDenied};
    }
    if (!exists) {
        return {fmt::format("{}: no such socket: is ecpaird running? (--socket PATH or --name NAME picks another)", socket),
                kExitUnreachable};
    }
    if (client_error.find("Connection refused") != std::string::npos) {
        return {fmt::format("{}: nobody listens there (ecpaird stopped or crashed)", socket), kExitUnreachable};
    }
    return {client_error, kExitUnreachable};
}

Expected<control::Response, DaemonFailure> ask_daemon(const std::string& socket, const control::Request& request) {
    auto response = control::call(socket, request);
    if (!response) return unexpected(describe_connection_failure(socket, response.error().message));
    if (!response->ok()) return unexpected(DaemonFailure{fmt::format("{}: {}", socket, response->error()), kExitRefused});
    return std::move(*response);
}

Expected<control::Response, int> call_daemon(const std::string& socket, const control::Request& request,
                                             std::ostream& err) {
    auto response = ask_daemon(socket, request);
    if (!response) {
        fmt::print(err, "ecpairctl: {}\n", response.error().message);
        return unexpected(response.error().exit_code);
    }
    return std::move(*response);
}

int run_socket_only_request(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                            const char* command, void (*fill)(control::Request&), const char* done) {
    SocketOptions sockets;
    boost::program_options::options_description options("ecpairctl options");
    add_socket_options(options, sockets);
    boost::program_options::variables_map vm;
    const std::string usage = fmt::format("ecpairctl {} [--socket PATH]", command);
    if (auto rc = parse_arguments(args, options, nullptr, vm, command, usage, out, err)) return *rc;
    control::Request request;
    fill(request);
    if (auto response = call_daemon(sockets.path(), request, err); !response) return response.error();
    fmt::print(out, "{}\n", done);
    return kExitOk;
}

}  // namespace ecpair::ctl
