#pragma once
// What every ecpairctl command that talks to ecpaird shares: the socket
// options (--socket PATH, --name NAME), argument parsing that reports a
// mistake in one line, and one request/response with the failure turned
// into one line on `err` and an exit code (exit_codes.hpp).

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "ecpair/common/expected.hpp"
#include "ecpair/control.pb.h"

namespace ecpair::ctl {

// --socket may be given more than once where a command takes a pair.
struct SocketOptions {
    std::vector<std::string> sockets;
    std::string name = "ecpaird";
    // The sockets given, or /run/ecpair/<name>.sock.
    std::vector<std::string> paths() const;
    std::string path() const { return paths().front(); }
};

void add_socket_options(boost::program_options::options_description& options, SocketOptions& sockets);

// Parses `args`: nullopt to go on, else the exit code (help printed: 0; a
// mistake: one line on `err`, 2).
std::optional<int> parse_arguments(const std::vector<std::string>& args,
                                   const boost::program_options::options_description& options,
                                   const boost::program_options::positional_options_description* positional,
                                   boost::program_options::variables_map& vm, const std::string& command,
                                   const std::string& usage, std::ostream& out, std::ostream& err);

// Why a daemon could not be asked, as one line and an exit code.
struct DaemonFailure {
    std::string message;
    int exit_code;
};

// The daemon's response when it accepted the request.
Expected<control::Response, DaemonFailure> ask_daemon(const std::string& socket, const control::Request& request);

// ask_daemon, the failure printed as "ecpairctl: <message>".
Expected<control::Response, int> call_daemon(const std::string& socket, const control::Request& request,
                                             std::ostream& err);

// A command that takes only --socket and sends one request: parses `args`,
// sends what `fill` puts into the request, prints `done` when the daemon
// accepted it; the exit code.
int run_socket_only_request(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                            const char* command, void (*fill)(control::Request&), const char* done);

// A connection failure in words an operator can act on (exposed for tests).
DaemonFailure describe_connection_failure(const std::string& socket, const std::string& client_error);

}  // namespace ecpair::ctl
