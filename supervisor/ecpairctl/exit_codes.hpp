#pragma once
// ecpairctl's exit codes, the same for every command that talks to ecpaird
// (docs/CLI.md). Scripts rely on them: never renumber.

namespace ecpair::ctl {

inline constexpr int kExitOk = 0;
inline constexpr int kExitRefused = 1;      // the daemon refused the request, or a check failed (compare)
inline constexpr int kExitUsage = 2;        // bad arguments
inline constexpr int kExitUnreachable = 3;  // no daemon answers at the socket (none there, not listening, no answer in time)
inline constexpr int kExitDenied = 4;       // the socket's mode and group do not let this user in

}  // namespace ecpair::ctl
