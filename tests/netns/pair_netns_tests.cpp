// A redundant pair over real interfaces (design.md §1): m1 and m2 in their
// own namespaces, ecsim's slave chain in a third, the master-master cable
// between them. m1 starts ACTIVE, m2 INACTIVE: m2 must forward every frame
// with the right bits, mirror m1's image every cycle, answer in the CMF,
// survive every line break, refuse a partner that differs, and take over
// by API without the slaves leaving OP.

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <catch2/catch.hpp>

#include "ecpair/control/image_history_comparison.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"
#include "tshark.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

const std::filesystem::path kEni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");

EcpairdSettings member(const std::string& name, const std::string& initial, const TempDir& dir,
                       const std::filesystem::path& eni = kEni, const std::string& extra = "") {
    EcpairdSettings s;
    s.name = name;
    s.main_if = name + "-main";
    s.red_if = name + "-red";
    s.eni = eni;
    s.dir = dir.path();
    s.extra_config = "cycle_time_us: " + std::to_string(kPairCycleUs) + "\nredundancy { enabled: true initial_state: " +
                     initial + " master_pd_out_size: 8 master_pd_in_size: 8 }\n" + extra;
    return s;
}

std::uint64_t little_endian(const std::string& bytes) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < bytes.size() && i < 8; ++i) v |= std::uint64_t{static_cast<unsigned char>(bytes[i])} << (8 * i);
    return v;
}

bool all_slaves_op(const StatusReply& s) {
    return s.slaves_size() > 0 && std::all_of(s.slaves().begin(), s.slaves().end(),
                                              [](const auto& slave) { return slave.al_state() == "OP"; });
}

// The pair on a simulated segment, m1 ACTIVE in OP and m2 mirroring it.
struct Pair {
    explicit Pair(const std::string& m2_extra = "", const std::filesystem::path& m2_eni = kEni)
        : topology(Controllers::Pair),
          ecsim(topology.sim(), {kEni, "sim-main", std::string("sim-red"), dir.path(), 70}),
          m1(topology.m1(), member("m1", "ACTIVE", dir)),
          m2(topology.m2(), member("m2", "INACTIVE", dir, m2_eni, m2_extra)),
          m1_events(m1.socket()),
          m2_events(m2.socket()) {}

    void reach_mirrored_op() {
        const bool m1_op =
            m1.wait_for([](const StatusReply& s) { return s.master_state() == "OP" && all_slaves_op(s); }, 30s)
                .has_value();
        const bool m2_mirrors = m1_op && m2.wait_for(
                                             [](const StatusReply& s) {
                                                 return s.redundancy().red_state() == "INACTIVE" &&
                                                        s.redundancy().partner_seen() && s.master_state() == "OP" &&
                                                        all_slaves_op(s);
                                             },
                                             10s)
                                             .has_value();
        if (!m1_op || !m2_mirrors) FAIL("m1:\n" << m1.log() << "\nm2:\n" << m2.log());
    }

    // Compares the image histories: every cycle m1 recorded as the ACTIVE
    // and m2 as its mirror must agree, and no cycle may have been sent by both.
    void check_mirror(std::size_t at_least) const {
        const auto comparison = ecpair::control::compare_image_histories(m1.image_history(), m2.image_history());
        INFO(comparison.describe() << "\nm2's events:\n" << m2_events.dump());
        CHECK(comparison.common_cycles >= at_least);
        CHECK(comparison.differ.empty());
        CHECK(comparison.both_active.empty());
    }

    TempDir dir{"ecpair-pair"};
    RingTopology topology;
    EcsimProcess ecsim;
    EcpairdProcess m1;
    EcpairdProcess m2;
    EventRecorder m1_events;
    EventRecorder m2_events;
};

// Byte 0 of the source MAC without the retry index, per interface of a capture.
std::set<int> byte0_values(const std::filesystem::path& capture) {
    const auto r = run_tshark(capture, {"-T", "fields", "-e", "eth.src"});
    std::set<int> values;
    for (const auto& line : r.lines) {
        if (line.size() >= 2) values.insert(std::stoi(line.substr(0, 2), nullptr, 16) & 0x8F);
    }
    return values;
}

}  // namespace

TEST_CASE("the INACTIVE mirrors the ACTIVE's image every cycle and master PD goes both ways",
          "[netns][redundancy][pair]") {
    Pair pair;
    pair.reach_mirrored_op();
    // 2000 cycles in OP from here (reaching OP may have taken a retry of the start-up scan).
    const auto in_op_from = pair.m1.status().timing().cycles();
    REQUIRE(pair.m1.wait_for([in_op_from](const StatusReply& s) { return s.timing().cycles() > in_op_from + 2000; }, 20s));

    pair.check_mirror(1000);
    // m2 stood by all along (a takeover here would be a false failover).
    for (const auto& event : pair.m2_events.events()) CHECK(event.kind() != "takeover");

    const auto m1 = pair.m1.status();
    const auto m2 = pair.m2.status();
    // The slave state image: presence and states as the ACTIVE has them.
    REQUIRE(m1.slaves_size() == m2.slaves_size());
    for (int i = 0; i < m1.slaves_size(); ++i) {
        CHECK(m1.slaves(i).present() == m2.slaves(i).present());
        CHECK(m1.slaves(i).al_state() == m2.slaves(i).al_state());
    }
    CHECK(m2.master_state() == m1.master_state());
    // ACTIVE -> INACTIVE: m1 sends its cycle counter, m2 has a recent one;
    // INACTIVE -> ACTIVE: m2 echoes it, m1 gets a recent echo back.
    const auto sent = little_endian(m1.redundancy().master_pd_out());
    const auto echoed = little_endian(m1.redundancy().master_pd_in());
    const auto received = little_endian(m2.redundancy().master_pd_out());
    CHECK(sent > in_op_from);  // a cycle counter of now, not of the start
    CHECK(echoed > 0);
    CHECK(echoed <= sent);
    CHECK(sent - echoed < 1000);
    CHECK(received > 0);
    CHECK(m1.redundancy().partner_seen());
    CHECK(m2.redundancy().dropped_circulating() == 0);
    CHECK(m2.redundancy().dropped_damaged() == 0);
    CHECK(m1.counters().foreign_frames() == 0);
    CHECK(m1.loopback().mismatches() == 0);

    REQUIRE(pair.ecsim.stop() == 0);
    CHECK(count_malformed_ethercat_frames(pair.ecsim.pcap()) == 0);
}

TEST_CASE("frames carry the forwarding bits of design.md at every place of the ring", "[netns][redundancy][pair][tshark]") {
    Pair pair;
    pair.reach_mirrored_op();
    struct Place {
        const TestNamespace& ns;
        std::string interface;
        std::set<int> expected;  // what arrives there and what leaves there
    };
    // 0x08 arrives at the INACTIVE's MAIN, 0x88 at the ACTIVE's MAIN, 0x02 at
    // the INACTIVE's RED, 0x06 at the ACTIVE's RED; the other value is what
    // leaves by that adapter.
    const Place places[] = {
        {pair.topology.m2(), "m2-main", {0x08, 0x06}},
        {pair.topology.m1(), "m1-main", {0x88, 0x00}},
        {pair.topology.m2(), "m2-red", {0x02, 0x88}},
        {pair.topology.m1(), "m1-red", {0x06, 0x08}},
    };
    for (const auto& place : places) {
        INFO(place.interface);
        const auto file = pair.dir / (place.interface + ".pcapng");
        REQUIRE(capture(place.ns.name(), place.interface, 1, file) == 0);
        CHECK(byte0_values(file) == place.expected);
        CHECK(count_malformed_ethercat_frames(file) == 0);
    }
    // The frame ids: what m1 sends on MAIN (0x00) comes back on its RED
    // forwarded by m2 (0x06) under the same id.
    const auto file = pair.dir / "m1-red-ids.pcapng";
    REQUIRE(capture(pair.topology.m1().name(), "m1-red", 1, file) == 0);
    const auto lines = run_tshark(file, {"-T", "fields", "-e", "eth.src"}).lines;
    std::map<int, std::set<std::string>> ids;  // byte0 -> "id/nic"
    for (const auto& line : lines) {
        if (line.size() < 17) continue;
        ids[std::stoi(line.substr(0, 2), nullptr, 16) & 0x8F].insert(line.substr(3, 2));
    }
    CHECK(ids[0x06].size() > 10);
    CHECK(ids[0x08].size() > 10);
}

TEST_CASE("line breaks anywhere keep OP and the INACTIVE mirroring", "[netns][redundancy][pair][cable_redundancy]") {
    Pair pair;
    pair.reach_mirrored_op();
    auto still_mirroring = [&](const char* where) {
        INFO(where);
        std::this_thread::sleep_for(500ms);
        const auto before = pair.m2.status();
        std::this_thread::sleep_for(300ms);
        const auto m1 = pair.m1.status();
        const auto m2 = pair.m2.status();
        CHECK(m1.master_state() == "OP");
        CHECK(m1.redundancy().red_state() == "ACTIVE");
        CHECK(m2.redundancy().mirrored_cycle() > before.redundancy().mirrored_cycle());
        CHECK(m2.master_state() == "OP");
        // On a mismatch, m1's log says which cycle and slave, and what the ring did around it.
        std::string says;
        std::istringstream log(pair.m1.log());
        for (std::string line; std::getline(log, line);) {
            if (line.find("loopback") != std::string::npos || line.find("line break") != std::string::npos ||
                line.find("ring") != std::string::npos) {
                says += line + "\n";
            }
        }
        INFO("m1 said:\n" << says);
        CHECK(m1.loopback().mismatches() == 0);
    };
    REQUIRE(pair.ecsim.ctl("break 2").first == 0);
    CHECK(pair.m1_events.wait_for("line-break", "after slave 2", 5s));
    still_mirroring("between slave 2 and slave 3");
    REQUIRE(pair.ecsim.ctl("repair 2").first == 0);
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));

    pair.topology.pull(Cable::M1Main);
    still_mirroring("between m1 and slave 1");
    pair.topology.plug(Cable::M1Main);
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));

    pair.topology.pull(Cable::RingReturn);
    CHECK(pair.m1_events.wait_for("line-break", "after slave 5", 5s));
    still_mirroring("between slave 5 and m2");
    pair.topology.plug(Cable::RingReturn);
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));

    pair.topology.pull(Cable::MasterMaster);
    still_mirroring("on the master-master cable");
    CHECK(pair.m2.status().redundancy().bounced() > 0);
    pair.topology.plug(Cable::MasterMaster);
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.ring_state() == "closed"; }, 5s));

    std::this_thread::sleep_for(300ms);
    pair.check_mirror(1000);
    INFO(pair.m1_events.dump());
    const auto m2 = pair.m2.status();
    CHECK(m2.redundancy().dropped_damaged() == 0);
    REQUIRE(pair.ecsim.stop() == 0);
    CHECK(count_malformed_ethercat_frames(pair.ecsim.pcap()) == 0);
}

TEST_CASE("two ACTIVE masters both see the other's frames as foreign", "[netns][redundancy][pair]") {
    Pair pair;
    pair.reach_mirrored_op();
    REQUIRE(pair.m2.request_red_state("ACTIVE").empty());
    INFO(pair.m1_events.dump());
    INFO(pair.m2_events.dump());
    CHECK(pair.m1_events.wait_for("frame-response-error", "foreign source MAC", 5s));
    CHECK(pair.m2_events.wait_for("frame-response-error", "foreign source MAC", 5s));
    CHECK(pair.m1.status().counters().foreign_frames() > 0);
    CHECK(pair.m2.status().counters().foreign_frames() > 0);
}

TEST_CASE("a frame looping between two INACTIVE masters is forwarded at most once per adapter",
          "[netns][redundancy][pair]") {
    Pair pair;
    pair.reach_mirrored_op();
    // Both forced to standby, so that neither supervisor takes the bus:
    // m2 first, then m1, which finds no hot standby to hand over to and steps down.
    REQUIRE(pair.m2.force_standby(true).empty());
    REQUIRE(pair.m1.force_standby(true).empty());
    // The role and the supervisor's words are published apart: wait for both.
    REQUIRE(pair.m1.wait_for(
        [](const StatusReply& s) {
            return s.redundancy().red_state() == "INACTIVE" &&
                   s.supervisor().no_active().find("forced to standby") != std::string::npos;
        },
        5s));
    std::this_thread::sleep_for(200ms);
    const auto dropped = [&pair] {
        return pair.m1.status().redundancy().dropped_circulating() + pair.m2.status().redundancy().dropped_circulating();
    };
    const auto dropped_before = dropped();

    // One frame from "nobody" onto the master-master cable: m2 forwards it out
    // of its RED adapter (bit 0x80), it passes the slaves and reaches m1's
    // MAIN, and m1, which would also send it out of a RED adapter, finds that
    // bit set and drops it. Each adapter role forwards it at most once.
    {
        NamespaceScope inside(pair.topology.m1());
        auto probe = ecpair::link::PcapLink::open("m1-red");
        REQUIRE(probe);
        std::array<std::uint8_t, ecpair::wire::kMaxFrameSize> buffer{};
        ecpair::wire::EthernetHeader eth;
        eth.destination = ecpair::wire::MacAddress::broadcast();
        eth.source = ecpair::wire::MacAddress{{0x00, 0x42, 0x00, 0x0a, 0x0b, 0x0c}};
        ecpair::wire::FrameBuilder builder(buffer, eth);
        builder.append(ecpair::wire::DatagramHeader{ecpair::wire::Command::Brd, 0, 0x01300000}, 2);
        REQUIRE((*probe)->send(builder.finish()));
    }
    // Bounded wait for the drop (a loaded machine may take a while to pass one frame round).
    const auto give_up = std::chrono::steady_clock::now() + 5s;
    while (dropped() == dropped_before && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(20ms);
    CHECK(dropped() == dropped_before + 1);
    const auto after = pair.m2.status().redundancy();
    // Nothing keeps going round: the counters stand still, and it was dropped once only.
    std::this_thread::sleep_for(300ms);
    const auto later = pair.m2.status().redundancy();
    CHECK(later.forwarded_main() == after.forwarded_main());
    CHECK(later.forwarded_red() == after.forwarded_red());
    CHECK(dropped() == dropped_before + 1);
}

TEST_CASE("a partner with a different ENI is never mirrored", "[netns][redundancy][pair]") {
    TempDir files("ecpair-eni");
    // The same slaves, another file content: one comment more.
    std::ifstream in(kEni);
    std::stringstream text;
    text << in.rdbuf();
    const auto other = files / "changed.xml";
    std::ofstream(other) << text.str() << "<!-- changed -->\n";
    Pair pair("", other);
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.master_state() == "OP"; }, 30s));
    const auto m2 = pair.m2.wait_for([](const StatusReply& s) { return !s.redundancy().partner_mismatch().empty(); }, 10s);
    INFO(pair.m2.log());
    REQUIRE(m2);
    CHECK(m2->redundancy().partner_mismatch().find("ENI") != std::string::npos);
    CHECK(m2->redundancy().mirrored_cycle() == 0);
    CHECK_FALSE(m2->redundancy().partner_seen());
    CHECK(m2->master_state() == "INIT");
    CHECK(pair.m2_events.wait_for("partner-mismatch", "ENI", 5s));
}

TEST_CASE("a takeover by API from a mirrored OP keeps the slaves in OP without INIT", "[netns][redundancy][pair]") {
    Pair pair;
    pair.reach_mirrored_op();
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.loopback().cycles_checked() > 500; }, 20s));
    const std::string ecsim_log_before = pair.ecsim.log();

    REQUIRE(pair.m1.request_red_state("INACTIVE").empty());
    REQUIRE(pair.m2.request_red_state("ACTIVE").empty());
    CHECK(pair.m2_events.wait_for("takeover", "hot", 5s));
    const auto m2 = pair.m2.wait_for(
        [](const StatusReply& s) {
            return s.redundancy().red_state() == "ACTIVE" && s.loopback().cycles_checked() > 500 && all_slaves_op(s);
        },
        20s);
    INFO(pair.m2_events.dump());
    REQUIRE(m2);
    CHECK(m2->master_state() == "OP");
    CHECK(m2->loopback().mismatches() == 0);
    CHECK(m2->redundancy().partner_seen());
    CHECK(pair.m2_events.wait_for("topology-verified", "confirms", 10s));
    // m2 never went through INIT (no state change events at all on m2 but the mirrored OP)...
    for (const auto& e : pair.m2_events.events()) {
        if (e.kind() == "master-state-changed") CHECK(e.text().find("-> INIT") == std::string::npos);
    }
    // ...and no simulated slave left OP: ecsim logs every AL transition.
    const std::string after = pair.ecsim.log().substr(ecsim_log_before.size());
    CHECK(after.find("AL OP -> ") == std::string::npos);
    // And now m1 mirrors m2.
    REQUIRE(pair.m1.wait_for([](const StatusReply& s) { return s.redundancy().partner_seen(); }, 10s));
}
