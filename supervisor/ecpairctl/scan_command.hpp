#pragma once
// `ecpairctl scan --if IF [--eni FILE]`: scans a bus directly over an
// interface and lists the slaves like an operator's `slaves` view.

#include <iosfwd>
#include <string>
#include <vector>

namespace ecpair::ctl {

// Exit codes: 0 scanned (and everything matches the ENI when one is given),
// 1 the bus does not match the ENI, 2 bad arguments or ENI, 3 link or bus failure.
int run_scan_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace ecpair::ctl
