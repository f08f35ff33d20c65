#include "ecpaird_process.hpp"

#include <signal.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <fmt/format.h>

#include "ecpair/control/control_client.hpp"
#include "ecsim_process.hpp"

namespace ecpair::test {
namespace {

// ECPAIR_TEST_FORWARDING=KERNEL|USER|AUTO runs a pair's members on that
// store-and-forward path (redundancy.forwarding): the second ctest
// registration of the pair and failover suites sets it (tests/netns/CMakeLists.txt).
// `field` inside the configuration's redundancy block, when it has one.
void add_to_redundancy_block(std::string& config, const std::string& field) {
    const std::string block = "redundancy {";
    const auto at = config.find(block);
    if (at != std::string::npos) config.insert(at + block.size(), " " + field + " ");
}

std::string with_forwarding_from_environment(std::string config) {
    const char* path = std::getenv("ECPAIR_TEST_FORWARDING");
    if (path == nullptr || *path == '\0') return config;
    add_to_redundancy_block(config, fmt::format("forwarding: {}", path));
    return config;
}

// Under TSan the daemons' threads stall for tens of milliseconds (the
// instrumentation, not the code under test). The link guard's 50 ms would
// take a stalled member's links down, a 50 ms comm timeout would fail over
// from a stalled ACTIVE and 100 ms of partner silence would call the
// partner lost, in tests that check something else: TSan builds give them
// ten times as long (the main stage checks the timing).
std::string with_sanitizer_allowances(std::string config) {
#if defined(__SANITIZE_THREAD__)
    if (config.find("link_guard {") == std::string::npos) config += "link_guard { hang_timeout_ms: 500 }\n";
    if (config.find("comm_timeout_ms") == std::string::npos) add_to_redundancy_block(config, "comm_timeout_ms: 500");
    if (config.find("partner_silence_ms") == std::string::npos) {
        add_to_redundancy_block(config, "partner_silence_ms: 1000");
    }
#endif
    return config;
}

}  // namespace

EcpairdProcess::EcpairdProcess(const TestNamespace& ns, EcpairdSettings settings) : settings_(std::move(settings)) {
    {
        std::ostringstream out;
        out << "name: \"" << settings_.name << "\"\n"
            << "interfaces { main: \"" << settings_.main_if << "\"";
        if (!settings_.red_if.empty()) out << " red: \"" << settings_.red_if << "\"";
        out << " }\n"
            << "eni_path: \"" << settings_.eni.string() << "\"\n"
            << "cable_redundancy: " << (settings_.cable_redundancy ? "true" : "false") << "\n";
        if (settings_.cable_redundancy && settings_.split_lrw) out << "split_lrw: true\n";
        out << "demo { kind: " << settings_.demo << " }\n"
            << "control { path: \"" << socket().string() << "\" " << settings_.control_extra << " }\n"
            << "log_level: \"debug\"\n"
            << settings_.extra_config << "\n";
        std::ofstream(config()) << with_sanitizer_allowances(with_forwarding_from_environment(out.str()));
    }
    std::filesystem::remove(socket());
    process_.emplace(std::vector<std::string>{ecpaird_binary(), "--config", config().string()},
                     settings_.dir / (settings_.name + ".log"), &ns);
    if (settings_.wait_until_ready) wait_ready();
}

void EcpairdProcess::wait_ready() {
    const auto give_up = std::chrono::steady_clock::now() + kProgramStartGuard;
    // Ready is answering: the socket file appears at bind(), a moment before
    // the daemon listens, and a connect in between is refused.
    const auto answers = [this] {
        control::Request request;
        request.mutable_status()->set_max_variables(0);
        return std::filesystem::exists(socket()) && control::call(socket().string(), request).has_value();
    };
    while (!answers()) {
        if (!process_->running() || std::chrono::steady_clock::now() > give_up) {
            throw std::runtime_error("ecpaird did not come up:\n" + process_->log());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

void EcpairdProcess::signal(int signal_number) const { ::kill(process_->pid(), signal_number); }

control::StatusReply EcpairdProcess::status(std::uint32_t variables) const {
    control::Request request;
    request.mutable_status()->set_max_variables(variables);
    auto response = control::call(socket().string(), request);
    if (!response) throw std::runtime_error(response.error().message);
    if (!response->ok()) throw std::runtime_error(response->error());
    return response->status();
}

std::optional<control::StatusReply> EcpairdProcess::wait_for(
    const std::function<bool(const control::StatusReply&)>& ready, std::chrono::milliseconds timeout) const {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    std::optional<control::StatusReply> last;
    for (;;) {
        last = status();
        if (ready(*last)) return last;
        if (std::chrono::steady_clock::now() > give_up) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

std::string EcpairdProcess::command(const control::Request& request) const {
    auto response = control::call(socket().string(), request);
    if (!response) return response.error().message;
    return response->ok() ? std::string() : response->error();
}

std::string EcpairdProcess::request_state(const std::string& state) const {
    control::Request request;
    request.mutable_set_master_state()->set_state(state);
    return command(request);
}

std::string EcpairdProcess::request_red_state(const std::string& state) const {
    control::Request request;
    request.mutable_set_red_state()->set_state(state);
    return command(request);
}

std::string EcpairdProcess::switchover() const {
    control::Request request;
    request.mutable_switchover();
    return command(request);
}

std::string EcpairdProcess::force_standby(bool forced) const {
    control::Request request;
    request.mutable_force_standby()->set_forced(forced);
    return command(request);
}

control::Response EcpairdProcess::call(const control::Request& request) const {
    auto response = control::call(socket().string(), request);
    if (!response) throw std::runtime_error(response.error().message);
    return std::move(*response);
}

control::ImageHistoryReply EcpairdProcess::image_history() const {
    control::Request request;
    request.mutable_image_history();
    auto response = control::call(socket().string(), request);
    if (!response) throw std::runtime_error(response.error().message);
    return response->image_history();
}

EventRecorder::EventRecorder(std::filesystem::path socket) : socket_(std::move(socket)) {
    thread_ = std::thread([this] {
        control::Request request;
        request.mutable_watch_events();
        // Re-connects until stopped: a daemon that restarts keeps being watched.
        while (!stop_) {
            (void)control::stream(
                socket_.string(), request,
                [this](const control::Response& r) {
                    if (r.has_event()) {
                        // Every new connection replays the daemon's backlog: keep each event once.
                        const auto& e = r.event();
                        std::lock_guard lock(mutex_);
                        const bool seen = std::any_of(events_.begin(), events_.end(), [&e](const auto& known) {
                            return known.unix_time_ms() == e.unix_time_ms() && known.cycle() == e.cycle() &&
                                   known.kind() == e.kind() && known.text() == e.text();
                        });
                        if (!seen) events_.push_back(e);
                    }
                    return !stop_.load();
                },
                std::chrono::milliseconds(200));
        }
    });
}

EventRecorder::~EventRecorder() {
    stop_ = true;
    thread_.join();
}

std::vector<control::EventMessage> EventRecorder::events() const {
    std::lock_guard lock(mutex_);
    return events_;
}

std::optional<control::EventMessage> EventRecorder::wait_for(const std::string& kind, const std::string& text,
                                                             std::chrono::milliseconds timeout) const {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            for (const auto& e : events_) {
                if (e.kind() == kind && e.text().find(text) != std::string::npos) return e;
            }
        }
        if (std::chrono::steady_clock::now() > give_up) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

std::string EventRecorder::dump() const {
    std::lock_guard lock(mutex_);
    std::string out;
    for (const auto& e : events_) out += e.kind() + " " + e.text() + "\n";
    return out;
}

}  // namespace ecpair::test
