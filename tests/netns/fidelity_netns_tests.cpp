// Real-world shapes through real interfaces (issue 11): the synthetic ENIs
// of tests/data/eni_extra (mailbox SMs written with 0x36/0x32, mailbox-less
// digital terminals whose output SM is set only on the way to OP, and a
// tree with an EK1122 junction) reach OP through ecpaird with cable
// redundancy; the tree also through the pair; and a master that falls
// silent leaves the slaves to their SM watchdog, as real slaves do.

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

std::filesystem::path extra_eni(const std::string& file) {
    return fmt::format("{}/eni_extra/{}", ECPAIR_TEST_DATA_DIR, file);
}

const auto kTree = extra_eni("tree_ek1122_7slaves.xml");

bool all_slaves_op(const StatusReply& s) {
    return s.slaves_size() > 0 && std::all_of(s.slaves().begin(), s.slaves().end(),
                                              [](const auto& slave) { return slave.al_state() == "OP"; });
}

// Per slave position, ecsim's status words (al=..., code=..., name=...).
std::map<std::size_t, std::map<std::string, std::string>> ecsim_slaves(const EcsimProcess& ecsim) {
    std::map<std::size_t, std::map<std::string, std::string>> slaves;
    const std::string line = ecsim.ctl("status").second;
    std::size_t at = line.find(" | ");
    while (at != std::string::npos) {
        const std::size_t next = line.find(" | ", at + 3);
        std::istringstream words(line.substr(at + 3, next == std::string::npos ? std::string::npos : next - at - 3));
        std::size_t position = 0;
        words >> position;
        for (std::string word; words >> word;) {
            const auto eq = word.find('=');
            if (eq != std::string::npos) slaves[position][word.substr(0, eq)] = word.substr(eq + 1);
        }
        at = next;
    }
    return slaves;
}

EcpairdSettings master_settings(const std::filesystem::path& eni, const TempDir& dir) {
    EcpairdSettings s;
    s.eni = eni;
    s.dir = dir.path();
    return s;
}

EcpairdSettings pair_member(const std::string& name, const std::string& initial, const std::filesystem::path& eni,
                            const TempDir& dir) {
    EcpairdSettings s = master_settings(eni, dir);
    s.name = name;
    s.main_if = name + "-main";
    s.red_if = name + "-red";
    s.extra_config = "cycle_time_us: 1000\nredundancy { enabled: true initial_state: " + initial +
                     " master_pd_out_size: 8 master_pd_in_size: 8 }\n";
    return s;
}

struct SingleMaster {
    explicit SingleMaster(const std::filesystem::path& eni)
        : topology(Controllers::Single),
          ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70}),
          daemon(topology.m1(), master_settings(eni, dir)),
          events(daemon.socket()) {}

    StatusReply reach_op() {
        const auto op = daemon.wait_for([](const StatusReply& s) { return s.master_state() == "OP" && all_slaves_op(s); },
                                        45s);
        INFO(daemon.log());
        INFO(events.dump());
        REQUIRE(op);
        return *op;
    }

    TempDir dir{"ecpair-fidelity"};
    RingTopology topology;
    EcsimProcess ecsim;
    EcpairdProcess daemon;
    EventRecorder events;
};

}  // namespace

TEST_CASE("what configurators export for real slaves reaches OP through ecpaird with cable redundancy",
          "[netns][fidelity][cable_redundancy]") {
    const auto file = GENERATE(as<std::string>{}, "twincat_mailbox_irq_2slaves.xml",
                               "digital_io_device_emulation_3slaves.xml", "tree_ek1122_7slaves.xml");
    INFO(file);
    SingleMaster ring(extra_eni(file));
    const auto op = ring.reach_op();
    CHECK(op.ring_state() == "closed");
    CHECK(op.sequence_error().empty());
    const auto running = ring.daemon.wait_for(
        [](const StatusReply& s) { return s.counters().frames_sent() > 2000 && all_slaves_op(s); }, 20s);
    REQUIRE(running);
    CHECK(running->counters().wkc_errors() == 0);
    CHECK(running->loopback().mismatches() == 0);
    for (const auto& [position, slave] : ecsim_slaves(ring.ecsim)) {
        INFO("ecsim slave " << position << " " << slave.at("name"));
        CHECK(slave.at("al") == "OP");
        CHECK(slave.at("code") == "0x0000");
    }
    // Events raised by the state machine carry the real cycle, not 0.
    const auto scan = ring.events.wait_for("bus-scan-status", "match", 1s);
    REQUIRE(scan);
    CHECK(scan->cycle() > 0);
}

TEST_CASE("the tree reaches OP through the pair with cable redundancy, the INACTIVE mirroring it",
          "[netns][fidelity][redundancy][pair]") {
    TempDir dir("ecpair-fidelity-pair");
    RingTopology topology(Controllers::Pair);
    EcsimProcess ecsim(topology.sim(), {kTree, "sim-main", std::string("sim-red"), dir.path(), 70});
    EcpairdProcess m1(topology.m1(), pair_member("m1", "ACTIVE", kTree, dir));
    EcpairdProcess m2(topology.m2(), pair_member("m2", "INACTIVE", kTree, dir));
    const auto m1_op = m1.wait_for(
        [](const StatusReply& s) { return s.master_state() == "OP" && all_slaves_op(s) && s.loopback().cycles_checked() > 500; },
        45s);
    INFO("m1:\n" << m1.log());
    REQUIRE(m1_op);
    CHECK(m1_op->ring_state() == "closed");
    CHECK(m1_op->loopback().mismatches() == 0);
    CHECK(m1_op->counters().wkc_errors() == 0);
    const auto m2_mirror = m2.wait_for(
        [](const StatusReply& s) {
            return s.redundancy().red_state() == "INACTIVE" && s.redundancy().partner_seen() && s.master_state() == "OP" &&
                   all_slaves_op(s);
        },
        10s);
    INFO("m2:\n" << m2.log());
    REQUIRE(m2_mirror);
    CHECK(m2_mirror->slaves_size() == 7);
    for (const auto& [position, slave] : ecsim_slaves(ecsim)) CHECK(slave.at("al") == "OP");
}

TEST_CASE("a master that falls silent leaves the slaves to their SM watchdog: 0x001B, the digital terminal keeps OP",
          "[netns][fidelity][watchdog]") {
    SingleMaster ring(kTree);
    ring.reach_op();
    REQUIRE(ring.daemon.wait_for([](const StatusReply& s) { return s.loopback().cycles_checked() > 200; }, 20s));
    // ecpaird stops sending when it stops (docs/ARCHITECTURE.md "Shutdown").
    REQUIRE(ring.daemon.stop() == 0);
    std::map<std::size_t, std::map<std::string, std::string>> slaves;
    for (int i = 0; i < 100; ++i) {  // bounded: 10 s for a 100 ms watchdog
        slaves = ecsim_slaves(ring.ecsim);
        if (slaves.at(5).at("al") != "OP") break;
        std::this_thread::sleep_for(100ms);
    }
    INFO(ring.ecsim.log());
    // Term 5 (EL7201) has a stack: SAFEOP with the error flag and the SM watchdog code.
    CHECK(slaves.at(5).at("al") == "SAFEOP+ERR");
    CHECK(slaves.at(5).at("code") == "0x001b");
    // Term 3 (EL2008) runs in device emulation: its outputs are cleared, its AL state stays.
    CHECK(slaves.at(3).at("al") == "OP");
    CHECK(ring.ecsim.log().find("slave \"Term 3 (EL2008)\": SM watchdog expired") != std::string::npos);
    // Slaves without process data, or only inputs, have no watchdog to expire.
    for (const std::size_t position : {1u, 2u, 4u, 6u, 7u}) CHECK(slaves.at(position).at("al") == "OP");
}
