#pragma once
// ecpairctl's Hot-Connect commands (hot-connect.md §5), against a running ecpaird:
//   groups                           the groups with their members and presence,
//                                    the mismatch descriptors, the blocked ports
//   accept                           accept the topology change waiting (manual modes)
//   topology-change                  run the topology change state machine now
//   block-node [--mismatch N | --station S]
//                                    close the port in front of a mismatch (default:
//                                    the first) or of a slave: what hangs behind it is cut off
//   open-blocked-ports               open what block-node closed
//   port STATION PORT SETTING        a port's loop setting: auto, auto-close, open, closed
//   alias set STATION VALUE          program the station alias into the slave's SII
//                                    (taken over at its next power-on)
// Options and exit codes as the other daemon commands (daemon_commands.hpp);
// a refusal prints the daemon's error, which starts with its code
// (InvalidState, InvalidParam, SlaveNotPresent, NotFound, MasterRedStateInactive).

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace ecpair::ctl {

// nullopt when `command` is none of these; else the exit code.
std::optional<int> run_hot_connect_command(const std::string& command, const std::vector<std::string>& args,
                                           std::ostream& out, std::ostream& err);

// The lines of the usage text for these commands.
const char* hot_connect_usage();

}  // namespace ecpair::ctl
