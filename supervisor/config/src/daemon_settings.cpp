// Parsing is protobuf's TextFormat (syntax and unknown-field errors come
// with line and column); validation afterwards names the field and, where
// the parser recorded it, the line of the field.

#include "ecpair/config/daemon_settings.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include "ecpair/config.pb.h"

namespace ecpair::config {
namespace {

namespace pb = google::protobuf;

class FirstErrorCollector final : public pb::io::ErrorCollector {
public:
    void AddError(int line, pb::io::ColumnNumber column, const std::string& message) override {
        if (!error) error = ConfigError{{}, line + 1, column + 1, {}, message};
    }
    void AddWarning(int, pb::io::ColumnNumber, const std::string&) override {}
    std::optional<ConfigError> error;
};

// Where each field was written, to point errors at it.
struct Locations {
    pb::TextFormat::ParseInfoTree tree;

    std::pair<int, int> of(const pb::Message& message, const std::string& path) const {
        const pb::TextFormat::ParseInfoTree* node = &tree;
        const pb::Message* current = &message;
        std::stringstream parts(path);
        std::string part;
        std::vector<std::string> names;
        while (std::getline(parts, part, '.')) names.push_back(part);
        for (std::size_t i = 0; i < names.size(); ++i) {
            // A repeated field's element is named "field[index]".
            int index = -1;
            if (const auto bracket = names[i].find('['); bracket != std::string::npos) {
                index = std::atoi(names[i].c_str() + bracket + 1);
                names[i].resize(bracket);
            }
            const auto* field = current->GetDescriptor()->FindFieldByName(names[i]);
            if (field == nullptr) return {0, 0};
            if (field->is_repeated() != (index >= 0)) return {0, 0};
            if (index >= 0 && index >= current->GetReflection()->FieldSize(*current, field)) return {0, 0};
            if (i + 1 == names.size()) {
                const auto location = node->GetLocation(field, index);
                return {location.line + 1, location.column + 1};
            }
            node = node->GetTreeForNested(field, -1);
            if (node == nullptr || field->type() != pb::FieldDescriptor::TYPE_MESSAGE) return {0, 0};
            current = &current->GetReflection()->GetMessage(*current, field);
        }
        return {0, 0};
    }
};

eni::SlaveState to_state(config::TargetState state) {
    switch (state) {
        case config::INIT: return eni::SlaveState::Init;
        case config::PREOP: return eni::SlaveState::Preop;
        case config::SAFEOP: return eni::SlaveState::Safeop;
        default: return eni::SlaveState::Op;
    }
}

// The tap block; an error is (field, message).
Expected<tap_bridge::TapBridgeOptions, std::pair<std::string, std::string>> tap_settings(const config::Tap& tap,
                                                                                         bool redundancy) {
    using Error = std::pair<std::string, std::string>;
    if (!redundancy) {
        return unexpected(Error{"tap", "the TAP bridge rides on the pair's frames: it needs redundancy { enabled: true }"});
    }
    tap_bridge::TapBridgeOptions options;
    if (!tap.name().empty()) options.name = tap.name();
    if (options.name.size() > 15) {
        return unexpected(Error{"tap.name", fmt::format("'{}' is longer than the 15 characters of an interface name", options.name)});
    }
    std::size_t ipv4 = 0;
    for (int i = 0; i < tap.address_size(); ++i) {
        const std::string field = fmt::format("tap.address[{}]", i);
        auto address = tap_bridge::InterfaceAddress::parse(tap.address(i));
        if (!address) return unexpected(Error{field, address.error()});
        if (address->family == tap_bridge::InterfaceAddress::Family::Ipv4 && ++ipv4 > 1) {
            return unexpected(
                Error{field, fmt::format("'{}': at most one IPv4 address (any number of IPv6)", tap.address(i))});
        }
        options.addresses.push_back(*address);
    }
    if (!tap.mac().empty()) {
        const auto mac = wire::MacAddress::parse(tap.mac());
        if (!mac || mac->is_group() || *mac == wire::MacAddress{}) {
            return unexpected(Error{"tap.mac", fmt::format("'{}' is no unicast MAC address (aa:bb:cc:dd:ee:ff)", tap.mac())});
        }
        options.mac = *mac;
    }
    if (tap.has_poll_size()) options.poll_size = tap.poll_size();
    if (tap.has_mtu()) options.mtu = tap.mtu();
    if (auto mtu = tap_bridge::TapBridge::mtu_for(options); !mtu) {
        return unexpected(Error{tap.has_mtu() && options.poll_size >= tap_bridge::kMinPollData &&
                                        options.poll_size <= tap_bridge::kMaxBridgeDatagramData
                                    ? "tap.mtu"
                                    : "tap.poll_size",
                                mtu.error()});
    }
    if (tap.has_queue_frames()) {
        if (tap.queue_frames() < 1 || tap.queue_frames() > 4096) {
            return unexpected(Error{"tap.queue_frames", fmt::format("must be 1..4096 (got {})", tap.queue_frames())});
        }
        options.queue_frames = tap.queue_frames();
    }
    return options;
}

}  // namespace

std::string ConfigError::describe() const {
    std::string where = file;
    if (line > 0) where += fmt::format(":{}:{}", line, column);
    return field.empty() ? fmt::format("{}: {}", where, message) : fmt::format("{}: {}: {}", where, field, message);
}

Expected<DaemonSettings, ConfigError> parse_daemon_settings(const std::string& text, const std::string& name) {
    config::DaemonConfig proto;
    FirstErrorCollector errors;
    Locations locations;
    pb::TextFormat::Parser parser;
    parser.RecordErrorsTo(&errors);
    parser.WriteLocationsTo(&locations.tree);
    if (!parser.ParseFromString(text, &proto)) {
        ConfigError error = errors.error.value_or(ConfigError{{}, 0, 0, {}, "cannot parse"});
        error.file = name;
        return unexpected(error);
    }
    auto fail = [&](const std::string& field, std::string message) {
        const auto [line, column] = locations.of(proto, field);
        return unexpected(ConfigError{name, line, column, field, std::move(message)});
    };

    DaemonSettings s;
    if (!proto.name().empty()) s.name = proto.name();
    if (proto.interfaces().main().empty()) return fail("interfaces.main", "required (the adapter facing slave 1)");
    s.main_interface = proto.interfaces().main();
    s.red_interface = proto.interfaces().red();
    if (!s.red_interface.empty() && s.red_interface == s.main_interface) {
        return fail("interfaces.red", fmt::format("must differ from interfaces.main ('{}')", s.main_interface));
    }
    if (proto.eni_path().empty()) return fail("eni_path", "required");
    s.eni_path = proto.eni_path();
    if (proto.has_cycle_time_us()) {
        if (proto.cycle_time_us() < 100 || proto.cycle_time_us() > 100'000) {
            return fail("cycle_time_us", fmt::format("must be 100..100000 µs (got {})", proto.cycle_time_us()));
        }
        s.cycle_time = std::chrono::microseconds(proto.cycle_time_us());
        s.cycle_time_from_config = true;
    }
    s.cable_redundancy = proto.cable_redundancy();
    if (s.cable_redundancy && s.red_interface.empty()) {
        return fail("cable_redundancy", "needs interfaces.red");
    }
    s.split_lrw = proto.split_lrw();
    if (s.split_lrw && !s.cable_redundancy) return fail("split_lrw", "only applies with cable_redundancy");
    s.target_state = to_state(proto.target_state());
    switch (proto.demo().kind()) {
        case config::DemoApplication::WALKING_BIT: s.demo = DemoKind::WalkingBit; break;
        case config::DemoApplication::LOOPBACK_CHECK: s.demo = DemoKind::LoopbackCheck; break;
        default: s.demo = DemoKind::None; break;
    }
    if (proto.demo().step_cycles() != 0) s.demo_step_cycles = proto.demo().step_cycles();
    s.control_path = proto.control().path().empty() ? fmt::format("/run/ecpair/{}.sock", s.name) : proto.control().path();
    if (proto.control().mode() != 0) {
        if (proto.control().mode() > 0777) {
            return fail("control.mode", fmt::format("must be permission bits 0..0777 (got {:o})", proto.control().mode()));
        }
        s.control_mode = proto.control().mode();
    }
    s.control_group = proto.control().group();
    if (proto.control().request_timeout_ms() != 0) {
        if (proto.control().request_timeout_ms() < 100 || proto.control().request_timeout_ms() > 600'000) {
            return fail("control.request_timeout_ms",
                        fmt::format("must be 100..600000 ms (got {})", proto.control().request_timeout_ms()));
        }
        s.control_request_timeout = std::chrono::milliseconds(proto.control().request_timeout_ms());
    }
    if (proto.control().max_clients() != 0) {
        if (proto.control().max_clients() > 65'536) {
            return fail("control.max_clients", fmt::format("must be 1..65536 (got {})", proto.control().max_clients()));
        }
        s.control_max_clients = proto.control().max_clients();
    }
    if (proto.has_max_acyclic_frames_per_cycle()) {
        if (proto.max_acyclic_frames_per_cycle() < 1 || proto.max_acyclic_frames_per_cycle() > 16) {
            return fail("max_acyclic_frames_per_cycle",
                        fmt::format("must be 1..16 (got {})", proto.max_acyclic_frames_per_cycle()));
        }
        s.max_acyclic_frames_per_cycle = proto.max_acyclic_frames_per_cycle();
    }
    if (proto.has_realtime_priority()) {
        if (proto.realtime_priority() < 0 || proto.realtime_priority() > 99) {
            return fail("realtime_priority", fmt::format("must be 0..99 (got {})", proto.realtime_priority()));
        }
        s.realtime_priority = proto.realtime_priority();
    }
    if (!proto.log_level().empty()) {
        static constexpr std::string_view kLevels[] = {"trace", "debug", "info", "warn", "error", "critical", "off"};
        if (std::find(std::begin(kLevels), std::end(kLevels), proto.log_level()) == std::end(kLevels)) {
            return fail("log_level", fmt::format("'{}' is not one of trace, debug, info, warn, error, critical, off",
                                                 proto.log_level()));
        }
        s.log_level = proto.log_level();
    }
    if (proto.has_redundancy()) {
        const auto& r = proto.redundancy();
        auto& out = s.redundancy;
        out.enabled = r.enabled();
        if (out.enabled && s.red_interface.empty()) {
            return fail("redundancy.enabled", "a redundant pair needs interfaces.red (the master-master cable)");
        }
        out.start_active = r.initial_state() == config::ACTIVE;
        constexpr std::uint32_t kMaxMasterPd = 4096;
        if (r.master_pd_out_size() > kMaxMasterPd) {
            return fail("redundancy.master_pd_out_size", fmt::format("must be 0..{} bytes (got {})", kMaxMasterPd,
                                                                     r.master_pd_out_size()));
        }
        if (r.master_pd_in_size() > kMaxMasterPd) {
            return fail("redundancy.master_pd_in_size", fmt::format("must be 0..{} bytes (got {})", kMaxMasterPd,
                                                                    r.master_pd_in_size()));
        }
        out.master_pd_out_size = r.master_pd_out_size();
        out.master_pd_in_size = r.master_pd_in_size();
        switch (r.forwarding()) {
            case config::Redundancy::KERNEL: out.forwarding = ForwardingMode::Kernel; break;
            case config::Redundancy::USER: out.forwarding = ForwardingMode::User; break;
            default: out.forwarding = ForwardingMode::Auto; break;
        }
        if (r.has_update_slave_pd_in()) out.update_slave_pd_in = r.update_slave_pd_in();
        if (r.has_update_slave_pd_out()) out.update_slave_pd_out = r.update_slave_pd_out();
        // Times in ms, each within what makes sense for a pair of masters.
        struct TimeField {
            const char* name;
            bool present;
            std::uint32_t value;
            std::uint32_t low, high;
            std::chrono::milliseconds* into;
        };
        const TimeField times[] = {
            {"comm_timeout_ms", r.has_comm_timeout_ms(), r.comm_timeout_ms(), 2, 10'000, &out.comm_timeout},
            {"listen_time_ms", r.has_listen_time_ms(), r.listen_time_ms(), 1, 60'000, &out.listen_time},
            {"backoff_min_ms", r.has_backoff_min_ms(), r.backoff_min_ms(), 1, 1'000, &out.backoff_min},
            {"backoff_max_ms", r.has_backoff_max_ms(), r.backoff_max_ms(), 1, 10'000, &out.backoff_max},
            {"partner_silence_ms", r.has_partner_silence_ms(), r.partner_silence_ms(), 2, 60'000, &out.partner_silence},
        };
        for (const auto& t : times) {
            if (!t.present) continue;
            if (t.value < t.low || t.value > t.high) {
                return fail(std::string("redundancy.") + t.name,
                            fmt::format("must be {}..{} ms (got {})", t.low, t.high, t.value));
            }
            *t.into = std::chrono::milliseconds(t.value);
        }
        if (out.backoff_max <= out.backoff_min) {
            return fail(r.has_backoff_max_ms() ? "redundancy.backoff_max_ms" : "redundancy.backoff_min_ms",
                        fmt::format("backoff_max_ms ({}) must be larger than backoff_min_ms ({})",
                                    out.backoff_max.count(), out.backoff_min.count()));
        }
        // The timeout must outlast a few cycles, or every jitter is a failover.
        if (std::chrono::duration_cast<std::chrono::microseconds>(out.comm_timeout) < 3 * s.cycle_time) {
            return fail("redundancy.comm_timeout_ms",
                        fmt::format("must be at least 3 cycles ({} µs each; got {} ms)", s.cycle_time.count(),
                                    out.comm_timeout.count()));
        }
        out.start_in_forced_standby = r.start_in_forced_standby();
        out.takeover_from_differing_partner = r.takeover_from_differing_partner();
    }
    // The link guard protects the partner's ring: on by default in a pair.
    s.link_guard.enabled = proto.link_guard().has_enabled() ? proto.link_guard().enabled() : s.redundancy.enabled;
    if (proto.link_guard().hang_timeout_ms() != 0) {
        if (proto.link_guard().hang_timeout_ms() < 10 || proto.link_guard().hang_timeout_ms() > 60'000) {
            return fail("link_guard.hang_timeout_ms",
                        fmt::format("must be 10..60000 ms (got {})", proto.link_guard().hang_timeout_ms()));
        }
        s.link_guard.hang_timeout = std::chrono::milliseconds(proto.link_guard().hang_timeout_ms());
    }
    if (proto.has_tap()) {
        auto tap = tap_settings(proto.tap(), s.redundancy.enabled);
        if (!tap) return fail(tap.error().first, tap.error().second);
        if (!tap->mac) tap->mac = tap_bridge::default_mac(s.name, tap->name);
        s.tap = std::move(*tap);
    }
    if (proto.has_hot_connect()) {
        const auto& h = proto.hot_connect();
        auto& out = s.hot_connect;
        switch (h.mode()) {
            case config::HotConnect::MANUAL_PREOP: out.mode = HotConnectMode::ManualPreop; break;
            case config::HotConnect::MANUAL_NORESET: out.mode = HotConnectMode::ManualNoReset; break;
            default: out.mode = HotConnectMode::Automatic; break;
        }
        out.border_close = h.border_close();
        if (h.has_detection_timeout_ms()) {
            constexpr std::uint32_t kMin = 100;
            constexpr std::uint32_t kMax = 600000;
            if (h.detection_timeout_ms() < kMin || h.detection_timeout_ms() > kMax) {
                return fail("hot_connect.detection_timeout_ms",
                            fmt::format("must be {}..{} ms (got {})", kMin, kMax, h.detection_timeout_ms()));
            }
            out.detection_timeout = std::chrono::milliseconds(h.detection_timeout_ms());
        }
    }
    return s;
}

Expected<DaemonSettings, ConfigError> load_daemon_settings(const std::string& path) {
    std::ifstream in(path);
    if (!in) return unexpected(ConfigError{path, 0, 0, {}, "cannot open the file"});
    std::stringstream text;
    text << in.rdbuf();
    auto settings = parse_daemon_settings(text.str(), path);
    if (!settings) return settings;
    // A relative ENI path is relative to the config file.
    const std::filesystem::path eni(settings->eni_path);
    if (eni.is_relative()) {
        settings->eni_path = (std::filesystem::path(path).parent_path() / eni).lexically_normal().string();
    }
    return settings;
}

}  // namespace ecpair::config
