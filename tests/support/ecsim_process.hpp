#pragma once
// The real ecsim binary running in a test namespace: started with an ENI
// and its interfaces, ready once its control socket exists, scripted with
// `ecsim ctl`, stopped (pcap flushed) at the end.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "netns.hpp"

namespace ecpair::test {

struct EcsimSettings {
    std::filesystem::path eni;
    std::string main_if = "sim-main";
    std::optional<std::string> red_if;
    std::filesystem::path dir;  // control socket, capture and log go here
    int realtime_priority = 0;
};

class EcsimProcess {
public:
    // Starts ecsim inside `ns` and waits (bounded) for its control socket.
    // Throws std::runtime_error with ecsim's log if it does not come up.
    EcsimProcess(const TestNamespace& ns, EcsimSettings settings);

    std::filesystem::path control() const { return settings_.dir / "ecsim.sock"; }
    std::filesystem::path pcap() const { return settings_.dir / "ecsim.pcap"; }
    std::string log() const { return process_->log(); }
    bool running() { return process_->running(); }

    // `ecsim ctl --control ... <words>`: exit status and the reply line.
    std::pair<int, std::string> ctl(const std::string& request) const;
    // Stops ecsim (SIGTERM) and returns its exit status; the capture is complete afterwards.
    int stop();

    // The AL transitions out of OP the simulated slaves logged since `from`
    // (an offset into the log).
    std::size_t slaves_leaving_op(std::size_t from = 0) const;
    // The SM (process data) watchdog expiries logged since `from`: a slave in
    // device emulation keeps OP when its watchdog expires, but its outputs are
    // cleared, so "never left OP" alone does not prove it.
    std::size_t sm_watchdog_expiries(std::size_t from = 0) const;

private:
    std::size_t log_lines_since(std::size_t from, std::string_view marker) const;

    EcsimSettings settings_;
    std::optional<ChildProcess> process_;
};

// Paths of the project's programs in the build tree.
std::string ecsim_binary();
std::string ecpaird_binary();
std::string ecpairctl_binary();

}  // namespace ecpair::test
