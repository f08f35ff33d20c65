#include "ecsim_process.hpp"

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace ecpair::test {

std::string ecsim_binary() { return ECPAIR_ECSIM_BINARY; }
std::string ecpaird_binary() { return ECPAIR_ECPAIRD_BINARY; }
std::string ecpairctl_binary() { return ECPAIR_ECPAIRCTL_BINARY; }

EcsimProcess::EcsimProcess(const TestNamespace& ns, EcsimSettings settings) : settings_(std::move(settings)) {
    std::vector<std::string> argv{ecsim_binary(),   "--eni",       settings_.eni.string(), "--main-if",
                                  settings_.main_if, "--control",  control().string(),     "--pcap",
                                  pcap().string(),   "--log-level", "debug"};
    if (settings_.red_if) {
        argv.push_back("--red-if");
        argv.push_back(*settings_.red_if);
    }
    if (settings_.realtime_priority > 0) {
        argv.push_back("--realtime-priority");
        argv.push_back(std::to_string(settings_.realtime_priority));
    }
    process_.emplace(argv, settings_.dir / "ecsim.log", &ns);
    const auto give_up = std::chrono::steady_clock::now() + kProgramStartGuard;
    while (!std::filesystem::exists(control())) {
        if (!process_->running() || std::chrono::steady_clock::now() > give_up) {
            throw std::runtime_error("ecsim did not come up:\n" + process_->log());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

std::pair<int, std::string> EcsimProcess::ctl(const std::string& request) const {
    std::vector<std::string> argv{ecsim_binary(), "ctl", "--control", control().string()};
    std::istringstream words(request);
    for (std::string word; words >> word;) argv.push_back(word);
    ChildProcess client(argv, settings_.dir / "ecsim-ctl.log");
    const auto status = client.wait_for_exit(kProgramStartGuard);
    std::string output = client.log();
    while (!output.empty() && output.back() == '\n') output.pop_back();
    return {status.value_or(-1), output};
}

int EcsimProcess::stop() { return process_->stop(); }

std::size_t EcsimProcess::log_lines_since(std::size_t from, std::string_view marker) const {
    const auto text = log();
    std::size_t n = 0;
    for (auto at = text.find(marker, std::min(from, text.size())); at != std::string::npos;
         at = text.find(marker, at + marker.size()))
        ++n;
    return n;
}

std::size_t EcsimProcess::slaves_leaving_op(std::size_t from) const { return log_lines_since(from, "AL OP -> "); }

std::size_t EcsimProcess::sm_watchdog_expiries(std::size_t from) const {
    return log_lines_since(from, "SM watchdog expired");
}

}  // namespace ecpair::test
