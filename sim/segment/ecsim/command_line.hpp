#pragma once
// ecsim's command line:
//
//   ecsim --eni FILE --main-if IF [--red-if IF] [--pcap FILE] [--control PATH]
//         [--log-level LEVEL] [--realtime-priority N]
//         [--dc-drift-ppm MAX] [--dc-seed N] [--dc-cable-delay-ns N]
//         [--dc-forwarding-delay-ns N] [--dc-processing-delay-ns N]
//   ecsim ctl (--control PATH | --main-if IF) [--json] COMMAND [ARG...]
//   ecsim --help
//
// parse_command_line() only reads the arguments; it opens nothing. Any
// problem is a UsageError, which main() prints with the usage text and
// answers with exit status 2.

#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/sim/segment.hpp"
#include "exit_status.hpp"

namespace ecpair::ecsim {

struct RunOptions {
    std::filesystem::path eni;
    std::string main_if;
    std::optional<std::string> red_if;
    std::optional<std::filesystem::path> pcap;
    std::filesystem::path control;  // --control, or /run/ecsim/<main-if>.sock
    std::string log_level = "info";
    int realtime_priority = 0;  // SCHED_FIFO for the event loop when > 0
    sim::SegmentOptions segment;  // the clocks and delays (--dc-*)
};

struct CtlOptions {
    std::filesystem::path control;
    std::string request;  // the COMMAND words joined by single spaces (with --json last when given)
    bool json = false;    // print the JSON the response carries, without "ok "
};

struct HelpRequest {};

using Invocation = std::variant<RunOptions, CtlOptions, HelpRequest>;

struct UsageError {
    std::string message;
};

Expected<Invocation, UsageError> parse_command_line(const std::vector<std::string>& arguments);

std::filesystem::path default_control_path(const std::string& main_if);

std::string usage_text();

}  // namespace ecpair::ecsim
