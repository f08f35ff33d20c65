#pragma once
// Exit statuses of the ecsim program, in both of its modes.

namespace ecpair::ecsim {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;      // ecsim: could not start or failed; ctl: the response was "error: ..."
inline constexpr int kExitUsage = 2;        // bad command line
inline constexpr int kExitUnreachable = 3;  // ctl: nothing answers on the control socket

}  // namespace ecpair::ecsim
