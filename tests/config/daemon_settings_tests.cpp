// ecpaird's configuration: defaults, every validated field named in its
// error with the line it was written on, syntax errors located.

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpair/config/daemon_settings.hpp"

using ecpair::config::DemoKind;
using ecpair::config::parse_daemon_settings;

namespace {

const char* kMinimal = R"(
interfaces { main: "m1-main" }
eni_path: "/etc/ecpair/line.xml"
)";

std::string error_of(const std::string& text) {
    auto r = parse_daemon_settings(text, "test.textproto");
    REQUIRE_FALSE(r);
    return r.error().describe();
}

}  // namespace

TEST_CASE("a minimal config gets the documented defaults", "[config]") {
    auto s = parse_daemon_settings(kMinimal);
    REQUIRE(s);
    CHECK(s->name == "ecpaird");
    CHECK(s->main_interface == "m1-main");
    CHECK(s->red_interface.empty());
    CHECK(s->cycle_time == std::chrono::microseconds(1000));
    CHECK_FALSE(s->cycle_time_from_config);
    CHECK(s->target_state == ecpair::eni::SlaveState::Op);
    CHECK(s->demo == DemoKind::None);
    CHECK(s->control_path == "/run/ecpair/ecpaird.sock");
    CHECK(s->control_mode == 0660);
    CHECK(s->max_acyclic_frames_per_cycle == 2);
    CHECK(s->realtime_priority == 80);
}

TEST_CASE("a full config is read field by field", "[config]") {
    auto s = parse_daemon_settings(R"(
name: "m1"
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "line.xml"
cycle_time_us: 250
cable_redundancy: true
split_lrw: true
target_state: SAFEOP
demo { kind: LOOPBACK_CHECK step_cycles: 10 }
control { path: "/tmp/m1.sock" mode: 0600 group: "ecpair" }
max_acyclic_frames_per_cycle: 4
realtime_priority: 0
log_level: "debug"
)");
    REQUIRE(s);
    CHECK(s->name == "m1");
    CHECK(s->red_interface == "m1-red");
    CHECK(s->cycle_time == std::chrono::microseconds(250));
    CHECK(s->cycle_time_from_config);
    CHECK(s->cable_redundancy);
    CHECK(s->split_lrw);
    CHECK(s->target_state == ecpair::eni::SlaveState::Safeop);
    CHECK(s->demo == DemoKind::LoopbackCheck);
    CHECK(s->demo_step_cycles == 10);
    CHECK(s->control_path == "/tmp/m1.sock");
    CHECK(s->control_mode == 0600);
    CHECK(s->control_group == "ecpair");
    CHECK(s->max_acyclic_frames_per_cycle == 4);
    CHECK(s->realtime_priority == 0);
    CHECK(s->log_level == "debug");
}

TEST_CASE("validation errors name the field and its line", "[config]") {
    CHECK(error_of("eni_path: \"x.xml\"\n") == "test.textproto: interfaces.main: required (the adapter facing slave 1)");
    CHECK(error_of("interfaces { main: \"a\" }\n") == "test.textproto: eni_path: required");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncycle_time_us: 5\n") ==
          "test.textproto:3:1: cycle_time_us: must be 100..100000 µs (got 5)");
    CHECK(error_of("interfaces {\n  main: \"a\"\n  red: \"a\"\n}\neni_path: \"x\"\n") ==
          "test.textproto:3:3: interfaces.red: must differ from interfaces.main ('a')");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncable_redundancy: true\n") ==
          "test.textproto:3:1: cable_redundancy: needs interfaces.red");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nsplit_lrw: true\n") ==
          "test.textproto:3:1: split_lrw: only applies with cable_redundancy");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncontrol { mode: 4095 }\n") ==
          "test.textproto:3:11: control.mode: must be permission bits 0..0777 (got 7777)");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nlog_level: \"loud\"\n").find("log_level: 'loud' is not one of") !=
          std::string::npos);
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nmax_acyclic_frames_per_cycle: 0\n") ==
          "test.textproto:3:1: max_acyclic_frames_per_cycle: must be 1..16 (got 0)");
}

TEST_CASE("syntax errors and unknown fields are located", "[config]") {
    const auto unknown = error_of("interfaces { main: \"a\" }\ncycle_time: 5\n");
    CHECK(unknown.rfind("test.textproto:2:", 0) == 0);
    CHECK(unknown.find("cycle_time") != std::string::npos);
    const auto syntax = error_of("interfaces { main: \"a\" \n");
    CHECK(syntax.rfind("test.textproto:", 0) == 0);
    const auto wrong_type = error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncycle_time_us: \"fast\"\n");
    CHECK(wrong_type.rfind("test.textproto:3:", 0) == 0);
}

TEST_CASE("a missing file is named", "[config]") {
    auto r = ecpair::config::load_daemon_settings("/nonexistent/ecpaird.textproto");
    REQUIRE_FALSE(r);
    CHECK(r.error().describe() == "/nonexistent/ecpaird.textproto: cannot open the file");
}

TEST_CASE("redundancy settings: defaults, values, and their errors", "[config]") {
    auto plain = parse_daemon_settings(kMinimal);
    REQUIRE(plain);
    CHECK_FALSE(plain->redundancy.enabled);

    auto pair = parse_daemon_settings(R"(
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "x.xml"
redundancy { enabled: true initial_state: ACTIVE master_pd_out_size: 16 master_pd_in_size: 8 update_slave_pd_out: false }
)");
    REQUIRE(pair);
    CHECK(pair->redundancy.enabled);
    CHECK(pair->redundancy.start_active);
    CHECK(pair->redundancy.master_pd_out_size == 16);
    CHECK(pair->redundancy.master_pd_in_size == 8);
    CHECK(pair->redundancy.update_slave_pd_in);
    CHECK_FALSE(pair->redundancy.update_slave_pd_out);

    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nredundancy { enabled: true }\n") ==
          "test.textproto:3:14: redundancy.enabled: a redundant pair needs interfaces.red (the master-master cable)");
    CHECK(error_of("interfaces { main: \"a\" red: \"b\" }\neni_path: \"x\"\nredundancy { master_pd_in_size: 5000 }\n") ==
          "test.textproto:3:14: redundancy.master_pd_in_size: must be 0..4096 bytes (got 5000)");
}

TEST_CASE("the example configurations of a pair are valid and agree on everything but name and interfaces",
          "[config]") {
    std::vector<ecpair::config::DaemonSettings> members;
    for (const char* name : {"controller-a", "controller-b"}) {
        auto s = ecpair::config::load_daemon_settings(fmt::format("{}/../../deploy/config/{}.textproto", ECPAIR_TEST_DATA_DIR, name));
        INFO(name);
        REQUIRE(s);
        CHECK(s->name == name);
        CHECK(s->redundancy.enabled);
        CHECK_FALSE(s->redundancy.start_active);  // no initial role: the pair decides
        CHECK(s->cable_redundancy);
        CHECK(s->link_guard.enabled);
        members.push_back(*s);
    }
    const auto& a = members[0];
    const auto& b = members[1];
    CHECK(a.eni_path == b.eni_path);
    CHECK(a.cycle_time == b.cycle_time);
    CHECK(a.split_lrw == b.split_lrw);
    CHECK(a.max_acyclic_frames_per_cycle == b.max_acyclic_frames_per_cycle);
    CHECK(a.redundancy.master_pd_out_size == b.redundancy.master_pd_out_size);
    CHECK(a.redundancy.master_pd_in_size == b.redundancy.master_pd_in_size);
    CHECK(a.redundancy.update_slave_pd_in == b.redundancy.update_slave_pd_in);
    CHECK(a.redundancy.update_slave_pd_out == b.redundancy.update_slave_pd_out);
    CHECK(a.control_path != b.control_path);
}

TEST_CASE("link guard and operator socket settings: defaults, values, and their errors", "[config]") {
    auto plain = parse_daemon_settings(kMinimal);
    REQUIRE(plain);
    CHECK_FALSE(plain->link_guard.enabled);  // a single master: off unless asked for
    CHECK(plain->link_guard.hang_timeout == std::chrono::milliseconds(50));
    CHECK(plain->control_request_timeout == std::chrono::milliseconds(5000));
    CHECK(plain->control_max_clients == 2048);

    auto pair = parse_daemon_settings(R"(
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "x.xml"
redundancy { enabled: true }
)");
    REQUIRE(pair);
    CHECK(pair->link_guard.enabled);  // a pair member: on

    auto set = parse_daemon_settings(R"(
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "x.xml"
redundancy { enabled: true }
link_guard { enabled: false hang_timeout_ms: 200 }
control { request_timeout_ms: 250 max_clients: 10 }
)");
    REQUIRE(set);
    CHECK_FALSE(set->link_guard.enabled);
    CHECK(set->link_guard.hang_timeout == std::chrono::milliseconds(200));
    CHECK(set->control_request_timeout == std::chrono::milliseconds(250));
    CHECK(set->control_max_clients == 10);

    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nlink_guard { hang_timeout_ms: 5 }\n") ==
          "test.textproto:3:14: link_guard.hang_timeout_ms: must be 10..60000 ms (got 5)");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncontrol { request_timeout_ms: 1 }\n") ==
          "test.textproto:3:11: control.request_timeout_ms: must be 100..600000 ms (got 1)");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\ncontrol { max_clients: 100000 }\n") ==
          "test.textproto:3:11: control.max_clients: must be 1..65536 (got 100000)");
}

TEST_CASE("hot-connect settings: defaults, values, and their errors", "[config][hotconnect]") {
    using ecpair::config::HotConnectMode;
    const auto plain = ecpair::config::parse_daemon_settings("interfaces { main: \"a\" }\neni_path: \"x\"\n", "t");
    REQUIRE(plain);
    CHECK(plain->hot_connect.mode == HotConnectMode::Automatic);
    CHECK_FALSE(plain->hot_connect.border_close);
    CHECK(plain->hot_connect.detection_timeout == std::chrono::milliseconds(15000));

    const auto set = ecpair::config::parse_daemon_settings(
        "interfaces { main: \"a\" }\neni_path: \"x\"\n"
        "hot_connect { mode: MANUAL_NORESET border_close: true detection_timeout_ms: 2000 }\n",
        "t");
    REQUIRE(set);
    CHECK(set->hot_connect.mode == HotConnectMode::ManualNoReset);
    CHECK(set->hot_connect.border_close);
    CHECK(set->hot_connect.detection_timeout == std::chrono::milliseconds(2000));

    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nhot_connect { detection_timeout_ms: 5 }\n") ==
          "test.textproto:3:15: hot_connect.detection_timeout_ms: must be 100..600000 ms (got 5)");
    CHECK(error_of("interfaces { main: \"a\" }\neni_path: \"x\"\nhot_connect { mode: SOMETIMES }\n").rfind(
              "test.textproto:3:", 0) == 0);
}

TEST_CASE("redundancy.forwarding: AUTO by default, KERNEL and USER as written, with a tap block too",
          "[config][kbpf]") {
    const std::string pair = "interfaces { main: \"m1-main\" red: \"m1-red\" }\neni_path: \"x.xml\"\n";
    auto defaults = parse_daemon_settings(pair + "redundancy { enabled: true }\n");
    REQUIRE(defaults);
    CHECK(defaults->redundancy.forwarding == ecpair::config::ForwardingMode::Auto);
    auto kernel = parse_daemon_settings(pair + "redundancy { enabled: true forwarding: KERNEL }\n");
    REQUIRE(kernel);
    CHECK(kernel->redundancy.forwarding == ecpair::config::ForwardingMode::Kernel);
    auto user = parse_daemon_settings(pair + "redundancy { enabled: true forwarding: USER }\n");
    REQUIRE(user);
    CHECK(user->redundancy.forwarding == ecpair::config::ForwardingMode::User);
    auto auto_with_tap = parse_daemon_settings(pair + "redundancy { enabled: true forwarding: AUTO }\ntap {}\n");
    REQUIRE(auto_with_tap);
    CHECK(auto_with_tap->redundancy.forwarding == ecpair::config::ForwardingMode::Auto);
    auto kernel_with_tap = parse_daemon_settings(pair + "redundancy { enabled: true forwarding: KERNEL }\ntap {}\n");
    REQUIRE(kernel_with_tap);
    CHECK(kernel_with_tap->redundancy.forwarding == ecpair::config::ForwardingMode::Kernel);
    CHECK(kernel_with_tap->tap.has_value());
    CHECK(error_of(pair + "redundancy { forwarding: FAST }\n").find("FAST") != std::string::npos);
}
