// Hot-Connect over real interfaces (hot-connect.md §8): ecsim's segment with
// groups at junction ports, ecpaird in its own namespace. A 4-slave group
// leaves and joins while the master stays in OP, with no cycle lost and no
// WKC error on the slaves that stay; an unknown slave is blocked and let in
// again with ecpairctl; the manual mode waits for an accept and border close
// keeps a stranger out; in a pair the INACTIVE answers like the ACTIVE, a
// change is mirrored, and a takeover in the middle of a change finishes it.
// Where slaves stay on the bus, ecsim's log proves they never left OP and
// their SM watchdog never expired.

#include <algorithm>
#include <fstream>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpair/sim/eni_generator.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

constexpr auto kReachOp = 30s;
constexpr auto kChange = 10s;

// 3 line slaves (junctions 1 and 2 carry the groups at port D), 2 groups of 4.
std::filesystem::path grouped_eni(const TempDir& dir) {
    ecpair::sim::GeneratedEniOptions options;
    options.slaves = 3;
    options.groups = 2;
    options.group_slaves = 4;
    options.input_bytes = 8;
    options.output_bytes = 6;
    const auto path = dir / "hotconnect.xml";
    std::ofstream(path) << ecpair::sim::generate_eni(options);
    return path;
}

bool all_present_in_op(const StatusReply& s) {
    return std::all_of(s.slaves().begin(), s.slaves().end(),
                       [](const auto& slave) { return !slave.present() || slave.al_state() == "OP"; });
}

std::size_t count_of(const EventRecorder& events, const std::string& kind) {
    const auto all = events.events();
    return static_cast<std::size_t>(std::count_if(all.begin(), all.end(), [&](const auto& e) { return e.kind() == kind; }));
}

// Waits for the n-th event of a kind (n counted from 1); its text.
std::optional<std::string> wait_nth(const EventRecorder& events, const std::string& kind, std::size_t n,
                                    std::chrono::milliseconds timeout) {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        std::size_t seen = 0;
        for (const auto& e : events.events()) {
            if (e.kind() == kind && ++seen == n) return e.text();
        }
        if (std::chrono::steady_clock::now() > give_up) return std::nullopt;
        std::this_thread::sleep_for(20ms);
    }
}

// ecpairctl with its output (stdout and stderr).
std::pair<int, std::string> ecpairctl(const TempDir& dir, const EcpairdProcess& daemon, std::vector<std::string> args) {
    std::vector<std::string> argv{ecpairctl_binary()};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), {"--socket", daemon.socket().string()});
    ChildProcess client(argv, dir / "ecpairctl.log");
    const auto status = client.wait_for_exit(10s);
    return {status.value_or(-1), client.log()};
}

ecpair::control::HotConnectGroupsReply groups_of(const EcpairdProcess& daemon) {
    ecpair::control::Request request;
    request.mutable_hc_groups();
    const auto response = daemon.call(request);
    REQUIRE(response.ok());
    return response.hc_groups();
}

std::string status_of_group(const ecpair::control::HotConnectGroupsReply& reply, std::uint32_t number) {
    for (const auto& g : reply.groups()) {
        if (g.number() == number) return g.status();
    }
    return "?";
}

EcpairdSettings master_settings(const std::string& name, const std::filesystem::path& eni, const TempDir& dir,
                                const std::string& extra = "") {
    EcpairdSettings s;
    s.name = name;
    s.main_if = name + "-main";
    s.red_if = name + "-red";
    s.eni = eni;
    s.dir = dir.path();
    s.demo = "WALKING_BIT";  // the loopback check would count an absent group's slaves as mismatches
    const bool own_hot_connect = extra.find("hot_connect") != std::string::npos;
    s.extra_config = fmt::format("cycle_time_us: 1000\n{}{}", own_hot_connect ? "" : "hot_connect { detection_timeout_ms: 5000 }\n",
                                   extra);
    return s;
}

// ecsim first (so that faults can be set before the master starts), then the master.
struct Single {
    explicit Single(bool ring = true, const std::string& extra = "")
        : topology(Controllers::Single),
          eni(grouped_eni(dir)),
          ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70}),
          ring_(ring),
          extra_(extra) {
        // Without the ring's return the line's end turns frames back (a master with one adapter).
        if (!ring_) topology.pull(Cable::RingReturn);
    }

    void start() {
        auto settings = master_settings("m1", eni, dir, extra_);
        if (!ring_) {
            settings.red_if.clear();
            settings.cable_redundancy = false;
        }
        daemon.emplace(topology.m1(), settings);
        events.emplace(daemon->socket());
        const auto op = daemon->wait_for(
            [](const StatusReply& s) {
                return s.master_state() == "OP" && all_present_in_op(s) && s.hot_connect().state() == "idle";
            },
            kReachOp);
        INFO(daemon->log());
        REQUIRE(op);
    }

    void ctl(const std::string& request) {
        const auto [status, reply] = ecsim.ctl(request);
        INFO(request << ": " << reply);
        REQUIRE(status == 0);
    }

    std::optional<std::string> next_change_done(std::size_t& seen) {
        return wait_nth(*events, "topology-change-done", ++seen, kChange);
    }

    TempDir dir{"ecpair-hc"};
    RingTopology topology;
    std::filesystem::path eni;
    EcsimProcess ecsim;
    std::optional<EcpairdProcess> daemon;
    std::optional<EventRecorder> events;

private:
    bool ring_;
    std::string extra_;
};

}  // namespace

TEST_CASE("a 4-slave group leaves and joins while the master stays in OP: no cycle lost, no WKC error",
          "[netns][hotconnect]") {
    Single bus;
    bus.ctl("group-off 2");
    bus.start();
    auto& m1 = *bus.daemon;
    CHECK(m1.status().hot_connect().groups_present() == 1);
    const auto before = m1.status().counters();
    const auto ecsim_log = bus.ecsim.log().size();
    std::size_t done = count_of(*bus.events, "topology-change-done");

    bus.ctl("group-on 2");
    auto text = bus.next_change_done(done);
    INFO(bus.events->dump());
    REQUIRE(text);
    CHECK_THAT(*text, Catch::Contains("topology change done: ok; 2 of 2 optional group(s) present"));
    const auto joined = m1.wait_for(
        [](const StatusReply& s) { return s.hot_connect().groups_present() == 2 && all_present_in_op(s); }, kChange);
    REQUIRE(joined);
    CHECK(std::all_of(joined->slaves().begin(), joined->slaves().end(), [](const auto& s) { return s.present(); }));

    bus.ctl("group-off 1");
    // The join may have ended in more than one change (a frame lost while the group came up is
    // looked at again): wait for the change that has group 1 gone, not for the next one.
    REQUIRE(bus.events->wait_for("topology-change-done", "ok; 1 of 2 optional group(s) present", kChange));
    const auto left = m1.wait_for([](const StatusReply& s) { return s.hot_connect().groups_present() == 1; }, kChange);
    REQUIRE(left);
    std::this_thread::sleep_for(300ms);  // a few hundred cycles in the new topology

    const auto after = m1.status(40);
    INFO("events at the end:\n" << bus.events->dump());
    CHECK(after.master_state() == "OP");
    CHECK(after.counters().wkc_errors() == before.wkc_errors());
    CHECK(count_of(*bus.events, "cyclic-wkc-error") == 0);
    // Nothing died inside the segment while the group came and went; a frame the master counted
    // as lost is one that came back late (the machine was busy), not one the change took.
    const auto [ecsim_rc, ecsim_status] = bus.ecsim.ctl("status");
    CHECK_THAT(ecsim_status, Catch::Contains(" destroyed=0 lost_no_link=0 lost_closed_port=0 "));
    // The slaves that stayed kept OP and got their outputs in time all along (a powered-off
    // group logs no AL transition); the joining group's slaves came up from INIT.
    CHECK(bus.ecsim.slaves_leaving_op(ecsim_log) == 0);
    CHECK(bus.ecsim.sm_watchdog_expiries(ecsim_log) == 0);
    const auto lost = after.counters().frames_lost() - before.frames_lost();
    const auto late = after.counters().late_copies() - before.late_copies();
    INFO("frames lost " << lost << ", late copies " << late);
    CHECK(lost <= late);
    CHECK(count_of(*bus.events, "detect-add-groups") >= 1);
    CHECK(count_of(*bus.events, "probe-all-groups") >= 1);
    // The absent group's input data reads 0 (LRD: nobody writes it), the others' inputs run.
    bool group1_zero = true;
    std::uint64_t junction_counter = 0;  // ecsim's slaves count frames in their first two input bytes
    std::size_t group1_variables = 0;
    for (const auto& v : after.inputs()) {
        if (v.name().rfind("Group 1 ", 0) == 0) {
            ++group1_variables;
            group1_zero = group1_zero && v.value() == 0;
        }
        if (v.name() == "Sim junction 1001.In 0") junction_counter |= v.value();
        if (v.name() == "Sim junction 1001.In 1") junction_counter |= v.value() << 8;
    }
    CHECK(group1_variables == 32);
    CHECK(group1_zero);
    CHECK(junction_counter != 0);

    const auto [rc, groups] = ecpairctl(bus.dir, m1, {"groups"});
    INFO(groups);
    CHECK(rc == 0);
    CHECK_THAT(groups, Catch::Contains("group 1 'Group 1': absent") && Catch::Contains("group 2 'Group 2': present") &&
                           Catch::Contains("Group 2 IO 4"));
}

TEST_CASE("an unknown slave is a mismatch, ecpairctl block-node cuts it off and open-blocked-ports lets it in again",
          "[netns][hotconnect]") {
    Single bus(/*ring=*/false);
    bus.start();
    auto& m1 = *bus.daemon;
    std::size_t done = count_of(*bus.events, "topology-change-done");
    bus.ctl("plug-unknown 1 C");
    auto text = bus.next_change_done(done);
    INFO(bus.events->dump());
    REQUIRE(text);
    CHECK_THAT(*text, Catch::Contains("groups refused"));
    const auto reply = groups_of(m1);
    REQUIRE(reply.mismatches_size() == 1);
    CHECK(reply.mismatches(0).kind() == "unexpected");
    CHECK(reply.mismatches(0).previous_station() == 1001);
    CHECK(reply.mismatches(0).previous_port() == "C");
    CHECK(reply.mismatches(0).found_vendor() == 0x0BADC0DE);

    auto [rc, out] = ecpairctl(bus.dir, m1, {"block-node"});
    INFO(out);
    CHECK(rc == 0);
    CHECK_THAT(out, Catch::Contains("station 1001 port C closed"));
    text = bus.next_change_done(done);
    REQUIRE(text);
    CHECK_THAT(*text, Catch::Contains("topology change done: ok"));
    CHECK(groups_of(m1).mismatches_size() == 0);

    std::tie(rc, out) = ecpairctl(bus.dir, m1, {"open-blocked-ports"});
    CHECK(rc == 0);
    CHECK_THAT(out, Catch::Contains("station 1001 port C open again"));
    text = bus.next_change_done(done);
    REQUIRE(text);
    CHECK_THAT(*text, Catch::Contains("groups refused"));

    std::tie(rc, out) = ecpairctl(bus.dir, m1, {"block-node", "--station", "4711"});
    CHECK(rc == 1);
    CHECK_THAT(out, Catch::Contains("NotFound: no slave with station 4711"));
    std::tie(rc, out) = ecpairctl(bus.dir, m1, {"accept"});
    CHECK(rc == 1);
    CHECK_THAT(out, Catch::Contains("InvalidState"));
    CHECK(m1.status().master_state() == "OP");
}

TEST_CASE("in manual mode a group waits in PREOP for ecpairctl accept, and border close keeps a stranger out",
          "[netns][hotconnect]") {
    Single bus(/*ring=*/false, "hot_connect { mode: MANUAL_PREOP border_close: true detection_timeout_ms: 5000 }\n");
    bus.ctl("group-off 1");
    bus.start();
    auto& m1 = *bus.daemon;
    REQUIRE(bus.events->wait_for("port-loop-changed", "border close", kChange));
    const auto on_bus = m1.status().hot_connect().slaves_on_bus();

    bus.ctl("plug-unknown 1 C");  // a port border close shut: nobody sees it
    std::this_thread::sleep_for(500ms);
    CHECK(m1.status().hot_connect().slaves_on_bus() == on_bus);

    bus.ctl("group-on 1");
    REQUIRE(bus.events->wait_for("hot-connect-accept-pending", "waiting for an accept", kChange));
    CHECK(status_of_group(groups_of(m1), 1) == "awaiting accept");
    CHECK_THAT(bus.ecsim.ctl("status").second, Catch::Contains("name=\"Group 1 IO 1\"") && Catch::Contains("al=PREOP"));
    std::size_t done = count_of(*bus.events, "topology-change-done");
    const auto [rc, out] = ecpairctl(bus.dir, m1, {"accept"});
    CHECK(rc == 0);
    const auto text = bus.next_change_done(done);
    INFO(bus.events->dump());
    REQUIRE(text);
    CHECK_THAT(*text, Catch::Contains("ok; 2 of 2"));
    REQUIRE(m1.wait_for([](const StatusReply& s) { return s.hot_connect().groups_present() == 2 && all_present_in_op(s); },
                        kChange));
}

TEST_CASE("in a pair the INACTIVE answers like the ACTIVE, and a takeover during a change finishes it",
          "[netns][hotconnect][redundancy]") {
    TempDir dir("ecpair-hc-pair");
    RingTopology topology(Controllers::Pair);
    const auto eni = grouped_eni(dir);
    EcsimProcess ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70});
    REQUIRE(ecsim.ctl("group-off 2").first == 0);
    const std::string pair = "redundancy { enabled: true initial_state: %s master_pd_out_size: 8 master_pd_in_size: 8 }\n";
    auto with_role = [&](const char* role) {
        std::string text = pair;
        text.replace(text.find("%s"), 2, role);
        return text;
    };
    EcpairdProcess m1(topology.m1(), master_settings("m1", eni, dir, with_role("ACTIVE")));
    EcpairdProcess m2(topology.m2(), master_settings("m2", eni, dir, with_role("INACTIVE")));
    EventRecorder m1_events(m1.socket());
    EventRecorder m2_events(m2.socket());
    const auto mirrored = [](const StatusReply& s) {
        return s.master_state() == "OP" && all_present_in_op(s) && s.redundancy().partner_seen();
    };
    REQUIRE(m1.wait_for(mirrored, kReachOp));
    REQUIRE(m2.wait_for(mirrored, kReachOp));
    const auto ecsim_log = ecsim.log().size();

    // The INACTIVE shows the groups as the ACTIVE does, and refuses to act.
    const auto on_m1 = groups_of(m1);
    const auto on_m2 = groups_of(m2);
    CHECK(status_of_group(on_m1, 2) == "absent");
    CHECK(status_of_group(on_m2, 2) == "absent");
    CHECK(status_of_group(on_m2, 1) == "present");
    ecpair::control::Request accept;
    accept.mutable_hc_accept();
    const auto refused = m2.call(accept);
    CHECK_FALSE(refused.ok());
    CHECK_THAT(refused.error(), Catch::StartsWith("MasterRedStateInactive"));

    // A change while mirroring: group 1 leaves, m2 shows it.
    REQUIRE(ecsim.ctl("group-off 1").first == 0);
    REQUIRE(wait_nth(m1_events, "topology-change-done", 1, kChange));
    const auto mirrored_change = m2.wait_for(
        [](const StatusReply& s) { return s.hot_connect().groups_present() == 0; }, kChange);
    INFO(m1_events.dump());
    REQUIRE(mirrored_change);

    // Group 2 powers on; as soon as m1 has found it, the roles change: m2 finishes the change.
    REQUIRE(ecsim.ctl("group-on 2").first == 0);
    REQUIRE(m1_events.wait_for("detect-add-groups", "groups added", kChange));
    REQUIRE(m1.request_red_state("INACTIVE").empty());
    REQUIRE(m2.request_red_state("ACTIVE").empty());
    REQUIRE(m2_events.wait_for("takeover", "hot", 5s));
    const auto finished = m2.wait_for(
        [](const StatusReply& s) {
            return s.redundancy().red_state() == "ACTIVE" && s.hot_connect().groups_present() == 1 && all_present_in_op(s);
        },
        kChange);
    INFO(m2_events.dump());
    INFO(m2.log());
    REQUIRE(finished);
    CHECK(status_of_group(groups_of(m2), 2) == "present");
    CHECK(finished->master_state() == "OP");
    // And the new INACTIVE mirrors the result.
    CHECK(m1.wait_for([](const StatusReply& s) { return s.hot_connect().groups_present() == 1; }, kChange));
    // Through the change and the takeover in its middle, no slave on the bus left OP or went
    // without outputs for its SM watchdog time (100 ms: the generated ENI writes no watchdog).
    INFO(ecsim.log().substr(ecsim_log));
    CHECK(ecsim.slaves_leaving_op(ecsim_log) == 0);
    CHECK(ecsim.sm_watchdog_expiries(ecsim_log) == 0);
}
