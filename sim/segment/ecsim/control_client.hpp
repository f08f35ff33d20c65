#pragma once
// `ecsim ctl`: sends one request line to a running ecsim's control socket
// and prints the response line on stdout. The exit status says how it went
// (exit_status.hpp: 0 ok, 1 "error: ...", 3 nothing answers).

#include "command_line.hpp"

namespace ecpair::ecsim {

int run_control_client(const CtlOptions& options);

}  // namespace ecpair::ecsim
