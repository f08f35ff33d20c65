// ecpairctl: the operator's command line for ecpair: offline helpers
// (validate an ENI, scan a bus) and the commands of a running ecpaird.

#include <iostream>
#include <string>
#include <vector>

#include "daemon_commands.hpp"
#include "ecpair/common/log.hpp"
#include "eni_command.hpp"
#include "scan_command.hpp"

namespace {

constexpr int kUsage = 2;

void print_usage(std::ostream& out) {
    out << "usage: ecpairctl COMMAND [ARGS]\n"
           "commands:\n"
           "  eni FILE                  validate and summarise an ENI file\n"
           "  scan --if IF [--red-if IF] [--eni FILE]\n"
           "                            scan the bus on interface IF (compare with an ENI)\n"
           "  status [--variables N]    the state of a running ecpaird\n"
           "  events [--for SECONDS]    watch a running ecpaird's events\n"
           "  state STATE               ask ecpaird for INIT, PREOP, SAFEOP or OP\n"
           "  red-state ACTIVE|INACTIVE make a controller of a pair ACTIVE or INACTIVE (no hand-off)\n"
           "  switchover                hand the bus to the partner without a lost cycle\n"
           "  force-standby             keep this controller from becoming ACTIVE\n"
           "  unforce-standby           release it\n"
           "  compare --socket A --socket B  check that a pair's images agree, cycle by cycle\n"
           "  (daemon commands take --socket PATH or --name NAME; default /run/ecpair/ecpaird.sock)\n"
           "  help                      this text\n";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        print_usage(std::cerr);
        return kUsage;
    }
    // Library logs are for problems here: an operator's command prints its own results.
    ecpair::set_log_level("warn");
    const std::string command = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    if (command == "eni") return ecpair::ctl::run_eni_command(args, std::cout, std::cerr);
    if (command == "scan") return ecpair::ctl::run_scan_command(args, std::cout, std::cerr);
    if (command == "status") return ecpair::ctl::run_status_command(args, std::cout, std::cerr);
    if (command == "events" || command == "watch") return ecpair::ctl::run_events_command(args, std::cout, std::cerr);
    if (command == "state") return ecpair::ctl::run_state_command(args, std::cout, std::cerr);
    if (command == "red-state") return ecpair::ctl::run_red_state_command(args, std::cout, std::cerr);
    if (command == "compare") return ecpair::ctl::run_compare_command(args, std::cout, std::cerr);
    using ecpair::ctl::PairCommand;
    if (command == "switchover") return ecpair::ctl::run_pair_command(args, std::cout, std::cerr, PairCommand::Switchover);
    if (command == "force-standby") {
        return ecpair::ctl::run_pair_command(args, std::cout, std::cerr, PairCommand::ForceStandby);
    }
    if (command == "unforce-standby") {
        return ecpair::ctl::run_pair_command(args, std::cout, std::cerr, PairCommand::UnforceStandby);
    }
    if (command == "help" || command == "--help" || command == "-h") {
        print_usage(std::cout);
        return 0;
    }
    std::cerr << "ecpairctl: unknown command '" << command << "'\n";
    print_usage(std::cerr);
    return kUsage;
}
