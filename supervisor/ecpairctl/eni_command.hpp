#pragma once
// `ecpairctl eni FILE`: loads an ENI offline, and either summarises it for a
// person (master, slave table, cyclic commands, process image, Hot-Connect
// groups, cable-redundancy remarks) or says exactly where it is wrong.

#include <iosfwd>
#include <string>
#include <vector>

namespace ecpair::ctl {

// `args` are the words after `eni`. Exit codes: 0 the ENI is valid (summary on
// `out`), 2 it is not (file:line: element path: message on `err`) or the
// arguments are wrong (usage on `err`).
int run_eni_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace ecpair::ctl
