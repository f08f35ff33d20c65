#pragma once
// Named spdlog loggers for library code. Library code never prints to
// stdout: every logger created here writes to stderr unless the program
// installs other sinks (ecpaird sends them to the journal).

#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

namespace ecpair {

// The logger for one module ("wire", "eni", "link", "sim", ...), created on
// first use with the process-wide sinks and level.
std::shared_ptr<spdlog::logger> logger(const std::string& module);

// Sets the level of every ecpair logger, present and future ("info", "debug"...).
// Returns false when the name is not a level.
bool set_log_level(const std::string& level_name);

// Replaces the sinks of every ecpair logger, present and future (ecpaird
// under systemd: the journal). Call early, before threads log.
void set_log_sinks(std::vector<spdlog::sink_ptr> sinks);

}  // namespace ecpair
