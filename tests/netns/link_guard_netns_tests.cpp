// The link guard over real interfaces (acontis REQ012): ecpaird's MAIN and
// RED go down when it is killed (kill -9), hangs (SIGSTOP, for hang_timeout)
// or stops, so the far ends (the slaves' ports, the partner) lose carrier;
// they come up when ecpaird starts, and after a hang only once this member
// may drive them: a pair member becomes INACTIVE first.

#include <poll.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <iostream>

#include <catch2/catch.hpp>

#include "ecpair/link/link_admin.hpp"
#include "ecpair/link/link_state_monitor.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

const std::filesystem::path kEni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");
// Bounds a wait for something that must happen; it measures nothing.
constexpr auto kPatience = 10s;
constexpr std::chrono::milliseconds kHangTimeout{150};

// IFF_UP of an interface, read over netlink inside its namespace.
bool admin_up(const TestNamespace& ns, const std::string& ifname) {
    NamespaceScope inside(ns);
    auto admin = ecpair::link::LinkAdmin::open();
    REQUIRE(admin);
    auto up = (*admin)->is_up(ifname);
    if (!up) FAIL(up.error().message);
    return *up;
}

// The interface has carrier (LOWER_UP): the far end of its cable is up.
bool carrier(const TestNamespace& ns, const std::string& ifname) {
    return ns.exec("ip link show " + ifname + " | grep -q LOWER_UP") == 0;
}

// No process lives in the namespace (asked from outside it).
bool nothing_runs_in(const TestNamespace& ns) {
    return run_command({"sh", "-c", "test -z \"$(ip netns pids " + ns.name() + ")\""}) == 0;
}

// Waits for `condition`; how long it took, or nullopt after `patience`.
std::optional<std::chrono::milliseconds> time_until(const std::function<bool()>& condition,
                                                    std::chrono::milliseconds patience = kPatience) {
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
        if (condition()) {
            return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start);
        }
        if (std::chrono::steady_clock::now() - start > patience) return std::nullopt;
        std::this_thread::sleep_for(2ms);
    }
}

// m1's two links and the far ends of their cables, as one picture.
struct MasterLinks {
    const RingTopology& topology;
    std::string main_peer_ns_side = "sim-main";

    const TestNamespace& far_of_red() const {
        return topology.controllers() == Controllers::Pair ? topology.m2() : topology.sim();
    }
    std::string far_red_if() const { return topology.controllers() == Controllers::Pair ? "m2-main" : "sim-red"; }

    bool all_down() const {
        return !admin_up(topology.m1(), "m1-main") && !admin_up(topology.m1(), "m1-red") &&
               !carrier(topology.sim(), "sim-main") && !carrier(far_of_red(), far_red_if());
    }
    bool all_up() const {
        return admin_up(topology.m1(), "m1-main") && admin_up(topology.m1(), "m1-red") &&
               carrier(topology.sim(), "sim-main") && carrier(far_of_red(), far_red_if());
    }
};

EcpairdSettings guarded(const TempDir& dir, const std::string& name, const std::string& extra) {
    EcpairdSettings s;
    s.name = name;
    s.main_if = name + "-main";
    s.red_if = name + "-red";
    s.eni = kEni;
    s.dir = dir.path();
    s.extra_config = "cycle_time_us: 1000\nlink_guard { enabled: true hang_timeout_ms: " +
                     std::to_string(kHangTimeout.count()) + " }\n" + extra;
    return s;
}

// SIGCONT on the way out, whatever happened: a stopped daemon cannot be stopped cleanly.
struct Resume {
    pid_t pid;
    ~Resume() { ::kill(pid, SIGCONT); }
};

std::vector<std::string> kinds_of(const EventRecorder& recorder) {
    std::vector<std::string> kinds;
    for (const auto& e : recorder.events()) kinds.push_back(e.kind());
    return kinds;
}

}  // namespace

TEST_CASE("link guard: ecpaird brings its links up at start and takes them down when it stops",
          "[netns][link_guard]") {
    TempDir dir{"ecpair-guard"};
    RingTopology topology(Controllers::Single);
    const MasterLinks links{topology};
    topology.m1().set_link("m1-main", false);
    topology.m1().set_link("m1-red", false);
    REQUIRE(time_until([&] { return links.all_down(); }));

    EcpairdProcess m1(topology.m1(), guarded(dir, "m1", ""));
    EventRecorder events(m1.socket());
    REQUIRE(time_until([&] { return links.all_up(); }));
    REQUIRE(events.wait_for("link-guard-links-up", "ecpaird started", kPatience));
    const auto status = m1.status();
    CHECK(status.link_guard().enabled());
    CHECK(status.link_guard().running());
    CHECK_FALSE(status.link_guard().links_down());
    CHECK(status.link_guard().hang_timeout_ms() == kHangTimeout.count());
    REQUIRE(m1.wait_for([](const StatusReply& s) { return s.timing().cycles() > 500; }, kPatience));

    CHECK(m1.stop() == 0);
    CHECK(links.all_down());  // down before ecpaird exited
    CHECK(m1.log().find("MAIN m1-main, RED m1-red down: ecpaird is shutting down") != std::string::npos);
    // The guard exited with ecpaird: nothing of either is left in the namespace.
    CHECK(nothing_runs_in(topology.m1()));
}

TEST_CASE("link guard: kill -9 of ecpaird takes its links down at both ends of both cables",
          "[netns][link_guard]") {
    TempDir dir{"ecpair-guard"};
    RingTopology topology(Controllers::Single);
    EcsimProcess ecsim(topology.sim(), {kEni, "sim-main", std::string("sim-red"), dir.path(), 0});
    const MasterLinks links{topology};
    EcpairdProcess m1(topology.m1(), guarded(dir, "m1", ""));
    REQUIRE(m1.wait_for([](const StatusReply& s) { return s.master_state() == "OP"; }, 30s));
    REQUIRE(links.all_up());

    // The slaves' ends of both cables, watched as the kernel reports them.
    std::unique_ptr<ecpair::link::LinkStateMonitor> far_ends;
    {
        NamespaceScope inside(topology.sim());
        auto opened = ecpair::link::LinkStateMonitor::open({"sim-main", "sim-red"});
        REQUIRE(opened);
        far_ends = std::move(*opened);
    }
    const auto killed_at = std::chrono::steady_clock::now();
    REQUIRE(::kill(m1.pid(), SIGKILL) == 0);
    REQUIRE(time_until([&] {
        pollfd entry{far_ends->selectable_fd(), POLLIN, 0};
        ::poll(&entry, 1, 100);
        (void)far_ends->read_changes();
        return far_ends->is_up("sim-main") == false && far_ends->is_up("sim-red") == false;
    }));
    const auto lost = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - killed_at);
    std::cout << "link guard: both slave-side ends without carrier " << static_cast<double>(lost.count()) / 1000.0 << " ms after kill -9"
              << std::endl;
    REQUIRE(time_until([&] { return links.all_down(); }));
    CHECK(m1.wait_for_exit(kPatience) == 128 + SIGKILL);
    CHECK(m1.log().find("ecpaird is gone (its end of the guard socket closed)") != std::string::npos);
    // The slaves' side saw both cables go: ecsim reports its ports without link.
    const auto sim_status = ecsim.ctl("status").second;
    INFO(sim_status);
    CHECK(sim_status.find("main=down") != std::string::npos);
    CHECK(sim_status.find("red=down") != std::string::npos);
    // The guard did its job and left.
    REQUIRE(time_until([&] { return nothing_runs_in(topology.m1()); }));
}

TEST_CASE("link guard: a hang takes the links down after hang_timeout - they come back once the cycle runs",
          "[netns][link_guard]") {
    TempDir dir{"ecpair-guard"};
    RingTopology topology(Controllers::Single);
    const MasterLinks links{topology};
    EcpairdProcess m1(topology.m1(), guarded(dir, "m1", ""));
    EventRecorder events(m1.socket());
    REQUIRE(m1.wait_for([](const StatusReply& s) { return s.timing().cycles() > 500; }, kPatience));
    REQUIRE(links.all_up());

    Resume resume{m1.pid()};
    const auto stopped_at = std::chrono::steady_clock::now();
    REQUIRE(::kill(m1.pid(), SIGSTOP) == 0);
    const auto down = time_until([&] { return links.all_down(); });
    REQUIRE(down);
    const auto after = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - stopped_at);
    std::cout << "link guard: links down " << after.count() << " ms after SIGSTOP (hang_timeout "
              << kHangTimeout.count() << " ms)" << std::endl;
    // Not before the timeout: the last heartbeat can have left at most one
    // heartbeat period (hang_timeout / 4) before the stop.
    CHECK(after >= kHangTimeout - kHangTimeout / 4);
    // While stopped the links stay down.
    std::this_thread::sleep_for(300ms);
    CHECK(links.all_down());

    REQUIRE(::kill(m1.pid(), SIGCONT) == 0);
    REQUIRE(time_until([&] { return links.all_up(); }));
    REQUIRE(events.wait_for("link-guard-links-up", "may drive its links again", kPatience));
    const auto kinds = kinds_of(events);
    const auto at = [&](const std::string& kind) { return std::find(kinds.begin(), kinds.end(), kind) - kinds.begin(); };
    INFO(events.dump());
    CHECK(at("link-guard-links-down") < at("link-guard-resumed"));
    CHECK(at("link-guard-resumed") < static_cast<long>(kinds.size()));
    const auto down_event = events.wait_for("link-guard-links-down", "the cycle stood still", 0ms);
    REQUIRE(down_event);
    CHECK(down_event->text().find("MAIN and RED") != std::string::npos);
    const auto status = m1.status();
    CHECK(status.link_guard().links_taken_down() == 1);
    CHECK_FALSE(status.link_guard().links_down());
    CHECK(status.link_guard().last_action().find("MAIN and RED down after cycle") != std::string::npos);
}

TEST_CASE("link guard: after a hang an ACTIVE pair member becomes INACTIVE before its links come up",
          "[netns][link_guard]") {
    TempDir dir{"ecpair-guard"};
    RingTopology topology(Controllers::Pair);
    const MasterLinks links{topology};
    const std::string pair = "redundancy { enabled: true initial_state: %s master_pd_out_size: 8 master_pd_in_size: 8 }\n";
    auto member = [&](const std::string& name, const std::string& initial) {
        std::string text = pair;
        text.replace(text.find("%s"), 2, initial);
        return guarded(dir, name, text);
    };
    EcpairdProcess m1(topology.m1(), member("m1", "ACTIVE"));
    EcpairdProcess m2(topology.m2(), member("m2", "INACTIVE"));
    EventRecorder m1_events(m1.socket());
    REQUIRE(m2.wait_for([](const StatusReply& s) { return s.redundancy().partner_seen(); }, kPatience));
    REQUIRE(links.all_up());
    CHECK(m1.status().link_guard().enabled());  // a pair member guards its links by default... and here explicitly

    Resume resume{m1.pid()};
    REQUIRE(::kill(m1.pid(), SIGSTOP) == 0);
    REQUIRE(time_until([&] { return links.all_down(); }));
    CHECK_FALSE(carrier(topology.m2(), "m2-main"));  // the partner's ring is open at m1

    REQUIRE(::kill(m1.pid(), SIGCONT) == 0);
    REQUIRE(time_until([&] { return links.all_up(); }));
    const auto status = m1.status();
    CHECK(status.redundancy().red_state() == "INACTIVE");
    REQUIRE(m1_events.wait_for("link-guard-links-up", "may drive its links again", kPatience));
    // The order on m1: the links go down (the guard, or first the carrier loss
    // that makes it give up the bus), it steps down to INACTIVE, and only then
    // the guard brings its links up again.
    const auto events = m1_events.events();
    INFO(m1_events.dump());
    const auto index_of = [&](const std::string& kind, const std::string& text = {}) {
        const auto it = std::find_if(events.begin(), events.end(), [&](const auto& e) {
            return e.kind() == kind && e.text().find(text) != std::string::npos;
        });
        return static_cast<std::size_t>(it - events.begin());
    };
    const auto down = index_of("link-guard-links-down");
    const auto inactive = index_of("red-state-changed", "ACTIVE -> INACTIVE");
    const auto up = index_of("link-guard-links-up", "may drive its links again");
    REQUIRE(down < events.size());
    REQUIRE(inactive < events.size());
    REQUIRE(up < events.size());
    CHECK(inactive < up);
    CHECK(down < up);
}

TEST_CASE("link guard: systemd's ExecStopPost line takes the configured links down, unless the guard is off",
          "[netns][link_guard]") {
    TempDir dir{"ecpair-guard"};
    RingTopology topology(Controllers::Single);
    const MasterLinks links{topology};
    const auto guard = (std::filesystem::path(ecpaird_binary()).parent_path() / "ecpair-linkguard").string();
    auto config = [&](const std::string& name, const std::string& link_guard) {
        const auto path = dir / (name + ".textproto");
        std::ofstream(path) << "name: \"m1\"\ninterfaces { main: \"m1-main\" red: \"m1-red\" }\neni_path: \"" << kEni.string()
                            << "\"\n" << link_guard << "\n";
        return path.string();
    };
    const auto off = config("off", "link_guard { enabled: false }");
    CHECK(topology.m1().exec(guard + " --config " + off + " --down") == 0);
    CHECK(links.all_up());

    const auto on = config("on", "link_guard { enabled: true }");
    CHECK(topology.m1().exec(guard + " --config " + on + " --down") == 0);
    CHECK(time_until([&] { return links.all_down(); }));

    const auto broken = config("broken", "link_guard { hang_timeout_ms: 1 }");
    CHECK(topology.m1().exec(guard + " --config " + broken + " --down 2>/dev/null") == 2);
}
