#pragma once
// The validated configuration of one ecpaird (from a .textproto, see
// proto/ecpair/config.proto). Loading reports the file, line and field of
// the first problem; everything after loading can trust these values.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/tap_bridge/tap_bridge.hpp"

namespace ecpair::config {

enum class DemoKind : std::uint8_t { None, WalkingBit, LoopbackCheck };

// Who forwards the INACTIVE's frames (redundancy.forwarding).
enum class ForwardingMode : std::uint8_t { Auto, Kernel, User };

struct RedundancySettings {
    bool enabled = false;
    bool start_active = false;
    std::uint32_t master_pd_out_size = 0;
    std::uint32_t master_pd_in_size = 0;
    bool update_slave_pd_in = true;
    bool update_slave_pd_out = true;
    std::chrono::milliseconds comm_timeout{50};
    std::chrono::milliseconds listen_time{200};
    std::chrono::milliseconds backoff_min{1};
    std::chrono::milliseconds backoff_max{10};
    std::chrono::milliseconds partner_silence{100};
    bool start_in_forced_standby = false;
    bool takeover_from_differing_partner = false;
    ForwardingMode forwarding = ForwardingMode::Auto;
};

struct LinkGuardSettings {
    bool enabled = false;
    std::chrono::milliseconds hang_timeout{50};
};

enum class HotConnectMode : std::uint8_t { Automatic, ManualPreop, ManualNoReset };

struct HotConnectSettings {
    HotConnectMode mode = HotConnectMode::Automatic;
    bool border_close = false;
    std::chrono::milliseconds detection_timeout{15000};
};

struct DaemonSettings {
    std::string name = "ecpaird";
    std::string main_interface;
    std::string red_interface;  // empty: no RED adapter
    std::string eni_path;       // resolved against the config file's directory
    std::chrono::microseconds cycle_time{1000};
    bool cycle_time_from_config = false;
    bool cable_redundancy = false;
    bool split_lrw = false;
    eni::SlaveState target_state = eni::SlaveState::Op;
    DemoKind demo = DemoKind::None;
    std::uint32_t demo_step_cycles = 1;
    std::string control_path;
    std::uint32_t control_mode = 0660;
    std::string control_group;
    std::chrono::milliseconds control_request_timeout{5000};
    std::uint32_t control_max_clients = 2048;
    std::uint32_t max_acyclic_frames_per_cycle = 2;
    int realtime_priority = 80;
    std::string log_level = "info";
    RedundancySettings redundancy;
    LinkGuardSettings link_guard;
    std::optional<tap_bridge::TapBridgeOptions> tap;  // the TAP bridge, when configured
    HotConnectSettings hot_connect;
};

struct ConfigError {
    std::string file;
    int line = 0;       // 1-based; 0 when the problem is not at one place in the file
    int column = 0;
    std::string field;  // "interfaces.main", "cycle_time_us"...
    std::string message;

    std::string describe() const;  // "ecpaird.textproto:4:3: cycle_time_us: must be 100..100000 µs (got 5)"
};

Expected<DaemonSettings, ConfigError> load_daemon_settings(const std::string& path);
// For tests and fuzzing: `name` stands in for the file name in errors.
Expected<DaemonSettings, ConfigError> parse_daemon_settings(const std::string& text, const std::string& name = "<memory>");

}  // namespace ecpair::config
