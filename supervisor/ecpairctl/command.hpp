#pragma once
// One ecpairctl command: its name, how it is called, one line on what it
// does, and the function that runs it on the words after its name. Every
// command is listed once, in command_table.cpp; `ecpairctl help` prints that
// list.

#include <iosfwd>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ecpair::ctl {

using CommandArgs = std::vector<std::string>;
using RunCommand = int (*)(const CommandArgs& args, std::ostream& out, std::ostream& err);

struct Command {
    std::string_view name;
    std::string_view synopsis;  // the arguments, as in a usage line
    std::string_view summary;
    RunCommand run;
};

std::span<const Command> commands();
const Command* find_command(std::string_view name);

}  // namespace ecpair::ctl
