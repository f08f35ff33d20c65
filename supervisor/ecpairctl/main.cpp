// ecpairctl: the operator's command line for ecpair: offline helpers
// (validate an ENI, scan a bus) and the commands of a running ecpaird. The
// commands are listed in command_table.cpp; exit codes in exit_codes.hpp and
// docs/CLI.md.

#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "command.hpp"
#include "ecpair/common/log.hpp"
#include "exit_codes.hpp"

namespace {

void print_usage(std::ostream& out) {
    fmt::print(out, "usage: ecpairctl COMMAND [ARGS]   (ecpairctl COMMAND --help for its options)\ncommands:\n");
    for (const auto& command : ecpair::ctl::commands()) {
        fmt::print(out, "  {:<10} {}\n  {:<10}   {}\n", command.name, command.synopsis, "", command.summary);
    }
    fmt::print(out, "commands that talk to ecpaird take --socket PATH or --name NAME (default /run/ecpair/ecpaird.sock)\n"
                    "exit codes: 0 done, 1 refused, 2 bad arguments, 3 no daemon answers, 4 permission denied (docs/CLI.md)\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        fmt::print(std::cerr, "ecpairctl: no command given (ecpairctl help lists them)\n");
        return ecpair::ctl::kExitUsage;
    }
    // Library logs are for problems here: an operator's command prints its own results.
    ecpair::set_log_level("warn");
    const std::string name = argv[1];
    if (name == "help" || name == "--help" || name == "-h") {
        print_usage(std::cout);
        return ecpair::ctl::kExitOk;
    }
    const auto* command = ecpair::ctl::find_command(name);
    if (command == nullptr) {
        fmt::print(std::cerr, "ecpairctl: unknown command '{}' (ecpairctl help lists them)\n", name);
        return ecpair::ctl::kExitUsage;
    }
    return command->run(std::vector<std::string>(argv + 2, argv + argc), std::cout, std::cerr);
}
