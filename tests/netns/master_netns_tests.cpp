// ecpaird as a single master over real interfaces: ecsim's slave chain in
// one namespace, the master in another, cable redundancy on (design.md §1
// with one controller). The master must reach OP from real and generated
// ENIs, move data both ways, survive a line break anywhere without losing a
// cycle to it, and name a missing or wrong slave.

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpair/sim/eni_generator.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"
#include "tshark.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

constexpr auto kReachOp = 30s;

std::filesystem::path generated_eni(const TempDir& dir, std::uint32_t slaves) {
    ecpair::sim::GeneratedEniOptions options;
    options.slaves = slaves;
    options.input_bytes = 8;
    options.output_bytes = 6;
    const auto path = dir / "generated.xml";
    std::ofstream(path) << ecpair::sim::generate_eni(options);
    return path;
}

std::filesystem::path shared_eni(const std::string& file) { return fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, file); }

// ecsim `status` is one line of key=value pairs.
std::string ecsim_status_line(const EcsimProcess& ecsim) { return ecsim.ctl("status").second; }

std::map<std::string, std::string> ecsim_counters(const EcsimProcess& ecsim) {
    const auto [status, line] = ecsim.ctl("status");
    std::map<std::string, std::string> values;
    std::istringstream words(line);
    for (std::string word; words >> word;) {
        const auto eq = word.find('=');
        if (eq != std::string::npos) values[word.substr(0, eq)] = word.substr(eq + 1);
    }
    return values;
}

EcpairdSettings single_master(const std::filesystem::path& eni, const TempDir& dir) {
    EcpairdSettings settings;
    settings.eni = eni;
    settings.dir = dir.path();
    return settings;
}

// A single master on a simulated ring, started and brought to OP.
struct SingleMasterRing {
    explicit SingleMasterRing(const std::filesystem::path& eni, int ecsim_priority = 70)
        : topology(Controllers::Single),
          ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), ecsim_priority}),
          daemon(topology.m1(), single_master(eni, dir)),
          events(daemon.socket()) {}

    StatusReply reach_op() {
        const auto status = daemon.wait_for([](const StatusReply& s) { return s.master_state() == "OP"; }, kReachOp);
        INFO(daemon.log());
        INFO(events.dump());
        REQUIRE(status);
        return *status;
    }

    TempDir dir{"ecpair-master"};
    RingTopology topology;
    EcsimProcess ecsim;
    EcpairdProcess daemon;
    EventRecorder events;
};

bool loopback_checked(const StatusReply& s, std::uint64_t cycles) { return s.loopback().cycles_checked() >= cycles; }

}  // namespace

TEST_CASE("ecpaird brings a generated segment to OP with cable redundancy and data flows both ways",
          "[netns][master][cable_redundancy]") {
    TempDir files("ecpair-eni");
    SingleMasterRing ring(generated_eni(files, 5));
    const auto op = ring.reach_op();
    CHECK(op.ring_state() == "closed");
    for (const auto& slave : op.slaves()) CHECK(slave.name().find("Sim IO") == 0);

    // The demo writes walking bits; ecsim's slaves echo them behind a counter.
    const auto checked = ring.daemon.wait_for([](const StatusReply& s) { return loopback_checked(s, 500); }, 20s);
    REQUIRE(checked);
    CHECK(checked->loopback().mismatches() == 0);
    CHECK(checked->loopback().slave_checks() >= 5 * 500);
    CHECK(checked->counters().wkc_errors() == 0);

    const auto first = ring.daemon.status(2);
    std::this_thread::sleep_for(100ms);
    const auto later = ring.daemon.status(2);
    REQUIRE(first.inputs_size() == 2);
    REQUIRE(later.inputs_size() == 2);
    // Input byte 0 of slave 1 is the low byte of its frame counter: it moves.
    CHECK(first.inputs(0).value() != later.inputs(0).value());
    for (const auto& slave : later.slaves()) {
        CHECK(slave.present());
        CHECK(slave.al_state() == "OP");
    }

    REQUIRE(ring.ecsim.stop() == 0);
    CHECK(count_ethercat_frames(ring.ecsim.pcap()) > 1000);
    CHECK(count_malformed_ethercat_frames(ring.ecsim.pcap()) == 0);
}

TEST_CASE("ecpaird reaches OP in ecsim from real ENIs with LRW split into LWR + LRD",
          "[netns][master][cable_redundancy][coe]") {
    const char* files[] = {"twincat_kpierczy_5slaves.xml", "ecengineer_rocos_elmo_3slaves_bcr.xml",
                           "twincat_cherryecat_cia402_1slave.xml", "ecengineer_rocos_elmo_7slaves.xml"};
    for (const char* file : files) {
        DYNAMIC_SECTION(file) {
            SingleMasterRing ring(shared_eni(file));
            const auto op = ring.reach_op();
            CHECK(op.sequence_error().empty());
            // The slave monitor reads every slave's AL status in rounds: wait for a round in OP.
            const auto all_op = [](const StatusReply& s) {
                return std::all_of(s.slaves().begin(), s.slaves().end(),
                                   [](const auto& slave) { return slave.al_state() == "OP"; });
            };
            const auto running = ring.daemon.wait_for(
                [&](const StatusReply& s) { return all_op(s) && s.loopback().cycles_checked() > 500; }, 20s);
            INFO(ring.events.dump());
            REQUIRE(running);
            CHECK(running->loopback().mismatches() == 0);
            CHECK(running->counters().wkc_errors() == 0);
            REQUIRE(ring.ecsim.stop() == 0);
            CHECK(count_malformed_ethercat_frames(ring.ecsim.pcap()) == 0);
        }
    }
}

TEST_CASE("a line break anywhere in OP raises line break and repair and loses no cycle to it",
          "[netns][master][cable_redundancy]") {
    TempDir files("ecpair-eni");
    SingleMasterRing ring(generated_eni(files, 5));
    ring.reach_op();
    REQUIRE(ring.daemon.wait_for([](const StatusReply& s) { return loopback_checked(s, 200); }, 20s));
    const auto before = ring.daemon.status();
    const auto dropped_before = ring.topology.frames_dropped_in_cables();

    for (const int k : {1, 2, 4}) {
        INFO("break after slave " << k);
        REQUIRE(ring.ecsim.ctl("break " + std::to_string(k)).first == 0);
        CHECK(ring.events.wait_for("line-break", "after slave " + std::to_string(k), 5s));
        const auto broken = ring.daemon.wait_for([](const StatusReply& s) { return s.ring_state() == "broken"; }, 5s);
        REQUIRE(broken);
        CHECK(broken->reachable_from_main() == static_cast<std::uint32_t>(k));
        std::this_thread::sleep_for(300ms);
        REQUIRE(ring.ecsim.ctl("repair " + std::to_string(k)).first == 0);
        REQUIRE(ring.daemon.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));
    }
    // Cables at the master: MAIN (ahead of slave 1) and the ring's return (behind slave 5).
    ring.topology.pull(Cable::M1Main);
    CHECK(ring.events.wait_for("link-down", "MAIN", 5s));
    std::this_thread::sleep_for(300ms);
    ring.topology.plug(Cable::M1Main);
    CHECK(ring.events.wait_for("link-up", "MAIN", 5s));
    ring.topology.pull(Cable::RingReturn);
    CHECK(ring.events.wait_for("line-break", "after slave 5", 5s));
    std::this_thread::sleep_for(300ms);
    ring.topology.plug(Cable::RingReturn);
    REQUIRE(ring.daemon.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));
    std::this_thread::sleep_for(200ms);

    const auto after = ring.daemon.status();
    INFO(ring.events.dump());
    // Nothing died inside the segment: every frame came back on one side or the other.
    const auto counters = ecsim_counters(ring.ecsim);
    CHECK(counters.at("destroyed") == "0");
    CHECK(counters.at("lost_no_link") == "0");
    CHECK(counters.at("hop_limit") == "0");
    // The master applied every cycle's data correctly...
    CHECK(after.loopback().mismatches() == 0);
    CHECK(after.counters().wkc_errors() == before.counters().wkc_errors());
    CHECK(after.master_state() == "OP");
    // ...and a frame it counted as lost is one that came back late (the
    // machine was busy), that the master could not send, or that was on its
    // way into a cable at the moment it was pulled (the master or ecsim sent
    // it before learning of the pull; the kernel counts it as dropped),
    // never one a break inside the ring took.
    const auto delta = [&](auto field) { return field(after.counters()) - field(before.counters()); };
    const auto lost = delta([](const auto& c) { return c.frames_lost(); });
    const auto late = delta([](const auto& c) { return c.late_copies(); });
    const auto unsent = delta([](const auto& c) { return c.send_errors(); });
    const auto swallowed = ring.topology.frames_dropped_in_cables() - dropped_before;
    INFO("lost " << lost << ", late " << late << ", unsent " << unsent << ", dropped in pulled cables " << swallowed
                 << ", ecsim: " << ecsim_status_line(ring.ecsim));
    CHECK(lost <= late + unsent + swallowed);
}

TEST_CASE("a missing mandatory slave keeps the master below PREOP with the mismatch named", "[netns][master]") {
    TempDir files("ecpair-eni");
    const auto eni = generated_eni(files, 4);
    TempDir dir("ecpair-master");
    RingTopology topology(Controllers::Single);
    EcsimProcess ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70});
    REQUIRE(ecsim.ctl("power-off 3").first == 0);
    EcpairdProcess daemon(topology.m1(), single_master(eni, dir));
    const auto stopped = daemon.wait_for([](const StatusReply& s) { return !s.sequence_error().empty(); }, 20s);
    INFO(daemon.log());
    REQUIRE(stopped);
    CHECK(stopped->master_state() == "INIT");
    CHECK(stopped->sequence_error().find("bus mismatch") != std::string::npos);
    CHECK(stopped->sequence_error().find("position 2") != std::string::npos);
    CHECK(stopped->sequence_error().find("Sim IO 1003") != std::string::npos);
}

TEST_CASE("a slave with another identity is named with configured and found identity", "[netns][master]") {
    TempDir files("ecpair-eni");
    const auto eni = generated_eni(files, 3);
    TempDir dir("ecpair-master");
    RingTopology topology(Controllers::Single);
    EcsimProcess ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70});
    REQUIRE(ecsim.ctl("insert-unknown 2").first == 0);
    EcpairdProcess daemon(topology.m1(), single_master(eni, dir));
    const auto stopped = daemon.wait_for([](const StatusReply& s) { return !s.sequence_error().empty(); }, 20s);
    INFO(daemon.log());
    REQUIRE(stopped);
    CHECK(stopped->master_state() == "INIT");
    CHECK(stopped->sequence_error().find("position 1") != std::string::npos);
    CHECK(stopped->sequence_error().find("0x0badc0de") != std::string::npos);
    CHECK(stopped->sequence_error().find("0x00000e5c") != std::string::npos);
}

TEST_CASE("a CoE emergency a drive sends in OP reaches the operator as an event naming the drive and the code",
          "[netns][master][coe][application]") {
    SingleMasterRing ring(shared_eni("ecengineer_rocos_elmo_1slave.xml"));
    ring.reach_op();
    const auto [status, reply] = ring.ecsim.ctl("emergency 1 0x8130 0x11 0102030405");
    INFO(reply);
    REQUIRE(status == 0);
    // Nobody talks to the idle mailbox: the mailbox service's poll finds SM1 full.
    const auto event = ring.events.wait_for("coe-emergency", "CoE emergency 0x8130", 5s);
    INFO(ring.events.dump());
    INFO(ring.daemon.log());
    REQUIRE(event);
    CHECK_THAT(event->text(), Catch::Contains("'Slave_1001 [Elmo Drive ]' (position 1, station 1001)") &&
                                  Catch::Contains("error register 0x11, data 01 02 03 04 05"));
    // One emergency, one event: a second read of the same SM1 would show within a second (poll every 10 ms).
    std::this_thread::sleep_for(1s);
    const auto all = ring.events.events();
    CHECK(std::count_if(all.begin(), all.end(), [](const auto& e) { return e.kind() == "coe-emergency"; }) == 1);
}
