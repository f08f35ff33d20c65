#pragma once
// The real ecpaird running in a test namespace: its configuration written
// from a few settings, ready once its operator socket exists; status and
// events read through the operator API like ecpairctl does.

#include <chrono>
#include <filesystem>
#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ecpair/control.pb.h"
#include "netns.hpp"

namespace ecpair::test {

// The cycle the namespace tests run a pair at. Under TSan the members and
// ecsim (instrumented too) cannot bring a 1 ms cycle's frames back in time
// on two cores: most cycles would be incomplete, the ACTIVE would rarely
// hear its partner and the TAP bridge would lose datagrams. The TSan stage
// looks for races, the main stage checks the timing.
#if defined(__SANITIZE_THREAD__)
inline constexpr int kPairCycleUs = 4000;
#else
inline constexpr int kPairCycleUs = 1000;
#endif

struct EcpairdSettings {
    std::string name = "m1";
    std::string main_if = "m1-main";
    std::string red_if = "m1-red";
    std::filesystem::path eni;
    std::filesystem::path dir;
    bool cable_redundancy = true;
    bool split_lrw = true;
    std::string demo = "LOOPBACK_CHECK";
    std::string extra_config;  // more textproto lines
    std::string control_extra;  // more fields of `control { ... }` (the path is set already)
    bool wait_until_ready = true;  // false: the constructor returns at once (call wait_ready())
};

class EcpairdProcess {
public:
    EcpairdProcess(const TestNamespace& ns, EcpairdSettings settings);
    // Waits (bounded) for the operator socket; throws with the log when the daemon does not come up.
    void wait_ready();

    std::filesystem::path socket() const { return settings_.dir / (settings_.name + ".sock"); }
    std::filesystem::path config() const { return settings_.dir / (settings_.name + ".textproto"); }
    std::string log() const { return process_->log(); }
    bool running() { return process_->running(); }
    int stop() { return process_->stop(); }
    std::optional<int> wait_for_exit(std::chrono::milliseconds timeout) { return process_->wait_for_exit(timeout); }
    // Sends a signal to the daemon (SIGKILL, SIGSTOP, SIGCONT...).
    void signal(int signal_number) const;

    // Throws std::runtime_error when the daemon does not answer.
    control::StatusReply status(std::uint32_t variables = 0) const;
    // Polls status until `ready` holds or `timeout` passes; the last status.
    std::optional<control::StatusReply> wait_for(const std::function<bool(const control::StatusReply&)>& ready,
                                                 std::chrono::milliseconds timeout) const;
    // Asks for a master state through the operator API; empty when accepted.
    std::string request_state(const std::string& state) const;
    // Asks for ACTIVE or INACTIVE; empty when accepted.
    std::string request_red_state(const std::string& state) const;
    // A zero-loss hand-off (ecpairctl switchover); empty when accepted.
    std::string switchover() const;
    // Forces this member to standby, or releases it; empty when accepted.
    std::string force_standby(bool forced) const;
    control::ImageHistoryReply image_history() const;
    // Any request; the response as it came (throws when the daemon does not answer).
    control::Response call(const control::Request& request) const;

    pid_t pid() const { return process_->pid(); }

private:
    std::string command(const control::Request& request) const;  // empty when accepted, else the error

    EcpairdSettings settings_;
    std::optional<ChildProcess> process_;
};

// Collects the event stream of one daemon on a thread of its own.
class EventRecorder {
public:
    explicit EventRecorder(std::filesystem::path socket);
    ~EventRecorder();
    EventRecorder(const EventRecorder&) = delete;
    EventRecorder& operator=(const EventRecorder&) = delete;

    std::vector<control::EventMessage> events() const;
    // Waits for an event of `kind` whose text contains `text`.
    std::optional<control::EventMessage> wait_for(const std::string& kind, const std::string& text,
                                                  std::chrono::milliseconds timeout) const;
    std::string dump() const;  // every event so far, one per line

private:
    std::filesystem::path socket_;
    mutable std::mutex mutex_;
    std::vector<control::EventMessage> events_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace ecpair::test
