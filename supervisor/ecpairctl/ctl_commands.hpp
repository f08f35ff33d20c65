#pragma once
// The run functions of ecpairctl's commands that talk to ecpaird, one file
// each (eni_command.hpp and scan_command.hpp have the offline ones);
// command_table.cpp lists them all.

#include "command.hpp"

namespace ecpair::ctl {

int run_status_command(const CommandArgs& args, std::ostream& out, std::ostream& err);      // status_command.cpp
int run_watch_command(const CommandArgs& args, std::ostream& out, std::ostream& err);       // watch_command.cpp
int run_events_command(const CommandArgs& args, std::ostream& out, std::ostream& err);      // events_command.cpp
int run_state_command(const CommandArgs& args, std::ostream& out, std::ostream& err);       // state_commands.cpp
int run_red_state_command(const CommandArgs& args, std::ostream& out, std::ostream& err);   // state_commands.cpp
int run_switchover_command(const CommandArgs& args, std::ostream& out, std::ostream& err);       // pair_commands.cpp
int run_force_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err);    // pair_commands.cpp
int run_unforce_standby_command(const CommandArgs& args, std::ostream& out, std::ostream& err);  // pair_commands.cpp
int run_compare_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // compare_command.cpp

}  // namespace ecpair::ctl
