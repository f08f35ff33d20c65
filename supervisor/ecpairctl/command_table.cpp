// Every ecpairctl command, once: `ecpairctl NAME ARGS` runs it, `ecpairctl
// help` lists them in this order. A new command is one file with its run
// function and one line here.

#include <algorithm>
#include <array>

#include "command.hpp"
#include "ctl_commands.hpp"
#include "eni_command.hpp"
#include "scan_command.hpp"

namespace ecpair::ctl {

std::span<const Command> commands() {
    static constexpr std::array kCommands{
        Command{"eni", "FILE", "validate and summarise an ENI file (offline)", run_eni_command},
        Command{"scan", "--if IF [--red-if IF] [--eni FILE]", "scan the bus on an interface, compare with an ENI",
                run_scan_command},
        Command{"status", "[--socket A [--socket B]] [--json] [--variables N]",
                "a running ecpaird as a table or JSON; two sockets: the pair view", run_status_command},
        Command{"watch", "[--socket A [--socket B]] [--interval S] [--count N]",
                "the status redrawn every second, with the latest events", run_watch_command},
        Command{"events", "[--for SECONDS] [--json]", "the daemon's events as they happen", run_events_command},
        Command{"state", "INIT|PREOP|SAFEOP|OP", "ask for a master state", run_state_command},
        Command{"switchover", "", "hand the bus to the partner without a lost cycle (on either member)",
                run_switchover_command},
        Command{"force-standby", "", "keep this member from becoming ACTIVE (an ACTIVE one hands over first)",
                run_force_standby_command},
        Command{"unforce-standby", "", "release it", run_unforce_standby_command},
        Command{"red-state", "ACTIVE|INACTIVE", "make a pair member ACTIVE or INACTIVE now (expert: no hand-off)",
                run_red_state_command},
        Command{"compare", "--socket A --socket B", "check that a pair's images agree, cycle by cycle",
                run_compare_command},
    };
    return kCommands;
}

const Command* find_command(std::string_view name) {
    const auto all = commands();
    const auto found = std::find_if(all.begin(), all.end(), [name](const Command& c) { return c.name == name; });
    return found == all.end() ? nullptr : &*found;
}

}  // namespace ecpair::ctl
