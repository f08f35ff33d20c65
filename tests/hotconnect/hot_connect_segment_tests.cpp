// Hot-Connect against a simulated segment, every use case of hot-connect.md
// §8 in one master without a cycle: start-up with a group missing, a group
// off and on, a mandatory slave failing, an unknown slave plugged (block
// node, open blocked ports), a group at a wrong port, a floating group, a
// duplicate, a slave refusing a state (lock-out), border close, the manual
// modes, the identification modes, the ETG.1020 race during a join, and
// programming the alias.

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "hot_connect_bench.hpp"

namespace ecpair::test {
namespace {

using hotconnect::GroupStatus;
using master::EventKind;
using hotconnect::TopologyResult;

constexpr std::uint8_t kOp = 0x08;
constexpr std::uint8_t kPreop = 0x02;
constexpr std::uint8_t kInit = 0x01;

GroupStatus status_of(const hotconnect::HotConnect& hc, std::size_t group) {
    for (const auto& g : hc.status().groups) {
        if (g.number == group) return g.status;
    }
    FAIL("no group " << group);
    return GroupStatus::Absent;
}

// Generated layout (3 line slaves, 2 groups of 2): file/segment positions
// 1 junction 1001, 2-3 group 1 (2101, 2102), 4 junction 1002, 5-6 group 2 (2201, 2202), 7 end 1003.

TEST_CASE("start-up with a group missing, then it is powered on and joins in OP", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(2, false)); });
    bench.start();
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Present);
    CHECK(status_of(*bench.hot_connect, 2) == GroupStatus::Absent);
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{5});  // 7 configured, 5 answer
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{5});

    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(2, true)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(done->b == 2);  // both optional groups present
    CHECK(bench.saw(hotconnect::events::kDetectAddGroups));
    CHECK(bench.saw(master::events::kSlavePresence, 4));  // ENI index of 2201
    CHECK(bench.al_state(5) == kOp);
    CHECK(bench.al_state(6) == kOp);
    CHECK(status_of(*bench.hot_connect, 2) == GroupStatus::Present);
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{7});
    CHECK(bench.expected_of(wire::Command::Lwr) == std::uint16_t{7});
    CHECK(bench.machine->presence() == std::vector<bool>(7, true));
}

TEST_CASE("an optional group goes off: WKCs corrected, the rest stays in OP", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(done->b == 1);
    CHECK(bench.saw(hotconnect::events::kProbeAllGroups));
    CHECK(bench.saw(master::events::kSlavePresence, 1));
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Absent);
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{5});
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{5});
    for (const std::size_t p : std::vector<std::size_t>{1, 4, 5, 6, 7}) CHECK(bench.al_state(p) == kOp);
    // and back: it joins again (through INIT, it was powered off).
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    REQUIRE(bench.wait_event(hotconnect::events::kTopologyChangeDone));
    CHECK(bench.al_state(2) == kOp);
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{7});
}

TEST_CASE("a mandatory slave fails: the change completes with an error, WKCs keep counting it", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.power_off(7)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::MandatoryMissing));
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{7});  // so cyclic WKC errors show
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{6});
    CHECK(bench.saw(master::events::kSlavePresence, 6));
}

TEST_CASE("an unknown slave plugged in is a mismatch, block node cuts it off, open blocked ports lets it in again",
          "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.plug_unknown_slave(1, 2)); });
    auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::GroupsRefused));
    CHECK(bench.saw(master::events::kBusMismatch));
    CHECK(bench.saw(master::events::kBusMismatchPlace));
    auto status = bench.hot_connect->status();
    REQUIRE(status.mismatches.size() == 1);
    CHECK(status.mismatches[0].previous_station == std::uint16_t{1001});
    CHECK(status.mismatches[0].previous_port == 'C');
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{8});  // it answers the BRD: no WKC error for that
    for (const std::size_t p : std::vector<std::size_t>{1, 2, 3, 4, 5, 6, 7}) CHECK(bench.al_state(p) == kOp);

    const auto blocked = bench.hot_connect->block_node(std::nullopt, std::nullopt);
    REQUIRE(blocked);
    CHECK(*blocked == hotconnect::PortRef{1001, 2});
    done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.hot_connect->status().mismatches.empty());
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{7});

    const auto opened = bench.hot_connect->open_blocked_ports();
    REQUIRE(opened);
    CHECK(opened->size() == 1);
    done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::GroupsRefused));
}

TEST_CASE("a pinned group at the wrong port is refused and can be blocked", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.start();
    // Group 2 moves from junction 2 port D to junction 1 port C (it keeps its power: still in OP there).
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.plug_group(2, 1, 2)); });
    const auto done = bench.wait_event([](const master::Event& e) {
        return e.kind == hotconnect::events::kTopologyChangeDone &&
               e.a != static_cast<std::uint32_t>(TopologyResult::Ok);
    });
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::GroupsRefused));
    const auto status = bench.hot_connect->status();
    REQUIRE_FALSE(status.mismatches.empty());
    CHECK_THAT(status.mismatches[0].text, Catch::Contains("looks like 'Group 2 IO 1', which belongs at station 1002 port D"));
    CHECK(status_of(*bench.hot_connect, 2) == GroupStatus::Absent);
}

TEST_CASE("a floating group is found at whatever port it is plugged into and joins", "[hotconnect][segment]") {
    auto options = grouped(1, 2);
    options.floating = true;
    HotConnectBench bench(options);
    bench.start();
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Absent);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.plug_group(1, 1, 3)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Present);
    CHECK(bench.al_state(4) == kOp);
    CHECK(bench.al_state(5) == kOp);
}

TEST_CASE("a duplicate of a group head: the first found is used, the second is unexpected", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.plug_duplicate(2, 4, 2)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    const auto status = bench.hot_connect->status();
    REQUIRE(status.mismatches.size() == 1);
    CHECK_THAT(status.mismatches[0].text, Catch::Contains("duplicate of 'Group 1 IO 1'"));
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Present);
}

TEST_CASE("a group slave refusing SAFEOP leaves its group out, and block node locks it out", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(2, false)); });
    bench.start();
    bench.with_segment([](sim::Segment& s) {
        REQUIRE(s.refuse_states_from(6, eni::SlaveState::Safeop));
        REQUIRE(s.set_group_power(2, true));
    });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::BringUpFailed));
    CHECK(status_of(*bench.hot_connect, 2) == GroupStatus::Refused);
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{5});
    for (const std::size_t p : std::vector<std::size_t>{1, 2, 3, 4, 7}) CHECK(bench.al_state(p) == kOp);
    const auto blocked = bench.hot_connect->block_node(std::nullopt, std::uint16_t{2201});
    INFO((blocked ? std::string() : blocked.error().message));
    REQUIRE(blocked);
    CHECK(*blocked == hotconnect::PortRef{1002, 3});
    const auto again = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    REQUIRE(again);
    CHECK(again->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(status_of(*bench.hot_connect, 2) == GroupStatus::Absent);
}

TEST_CASE("manual, PREOP: a new group waits in PREOP for the accept", "[hotconnect][segment]") {
    auto hc = HotConnectBench::fast();
    hc.mode = hotconnect::HotConnectMode::ManualPreop;
    HotConnectBench bench(grouped(), hc);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    CHECK_FALSE(bench.hot_connect->accept());  // nothing to accept yet
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    REQUIRE(bench.wait_event(hotconnect::events::kHotConnectAcceptPending));
    CHECK(bench.al_state(2) == kPreop);
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::AwaitingAccept);
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{5});
    REQUIRE(bench.hot_connect->accept());
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(bench.al_state(2) == kOp);
    CHECK(bench.al_state(3) == kOp);
    CHECK(bench.expected_of(wire::Command::Lrd) == std::uint16_t{7});
}

TEST_CASE("manual, no reset: a new group keeps its state until the accept", "[hotconnect][segment]") {
    auto hc = HotConnectBench::fast();
    hc.mode = hotconnect::HotConnectMode::ManualNoReset;
    HotConnectBench bench(grouped(), hc);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    REQUIRE(bench.wait_event(hotconnect::events::kHotConnectAcceptPending));
    CHECK(bench.al_state(2) == kInit);
    REQUIRE(bench.hot_connect->accept());
    REQUIRE(bench.wait_event(hotconnect::events::kTopologyChangeDone));
    CHECK(bench.al_state(2) == kOp);
}

TEST_CASE("border close: free ports are closed once running, a slave plugged there is not seen", "[hotconnect][segment]") {
    auto hc = HotConnectBench::fast();
    hc.border_close = true;
    HotConnectBench bench(grouped(), hc);
    bench.start();
    REQUIRE(bench.wait_event(hotconnect::events::kTopologyChangeDone));
    CHECK(bench.saw(hotconnect::events::kPortLoopChanged, 1001));  // junction 1 port C
    // A group's port stays open for it to come back; a free port does not let anybody in.
    bench.with_segment([](sim::Segment& s) {
        REQUIRE(s.set_group_power(1, false));
    });
    REQUIRE(bench.wait_event(hotconnect::events::kTopologyChangeDone));
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.plug_unknown_slave(1, 2)); });
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.hot_connect->status().mismatches.empty());
    CHECK(bench.expected_of(wire::Command::Brd) == std::uint16_t{7});  // the unknown slave is not seen
    CHECK(bench.al_state(2) == kOp);
}

TEST_CASE("identification by explicit device ID: the right ID joins, a wrong one is refused", "[hotconnect][segment]") {
    auto options = grouped(1, 2);
    options.identification = sim::GeneratedEniOptions::Identification::ExplicitDeviceId;
    HotConnectBench bench(options);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    bench.with_segment([](sim::Segment& s) {
        REQUIRE(s.set_id_selector(2, 999));
        REQUIRE(s.set_group_power(1, true));
    });
    auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::GroupsRefused));
    CHECK(bench.saw(master::events::kBusMismatchIdentification));
    CHECK(status_of(*bench.hot_connect, 1) == GroupStatus::Refused);
    bench.with_segment([](sim::Segment& s) {
        REQUIRE(s.set_id_selector(2, 101));
        REQUIRE(s.set_group_power(1, false));
    });
    REQUIRE(bench.wait_event(hotconnect::events::kTopologyChangeDone));
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.al_state(2) == kOp);
}

TEST_CASE("identification by input word is checked in SAFEOP", "[hotconnect][segment]") {
    auto options = grouped(1, 2);
    options.identification = sim::GeneratedEniOptions::Identification::InputWord;
    HotConnectBench bench(options);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.al_state(2) == kOp);
}

TEST_CASE("ETG.1020 during a join: the slave refuses SAFEOP with 0x0061, goes through INIT and joins",
          "[hotconnect][segment]") {
    HotConnectBench bench(grouped(1, 2));
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    // The head's SII alias is its identification (101); a rotary switch set to 101 races it.
    bench.with_segment([](sim::Segment& s) {
        REQUIRE(s.set_legacy_id_selector(2, 101));
        REQUIRE(s.set_group_power(1, true));
    });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.saw(master::events::kSlaveIdentificationUpdated, 1));
    CHECK(bench.al_state(2) == kOp);
}

TEST_CASE("a CoE drive group joins with its SDO InitCmds", "[hotconnect][segment]") {
    auto options = grouped(1, 2);
    options.coe_groups = true;
    HotConnectBench bench(options);
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, false)); });
    bench.start();
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(1, true)); });
    const auto done = bench.wait_event(hotconnect::events::kTopologyChangeDone);
    INFO(bench.seen_text());
    REQUIRE(done);
    CHECK(done->a == static_cast<std::uint32_t>(TopologyResult::Ok));
    CHECK(bench.al_state(2) == kOp);
    CHECK(bench.al_state(3) == kOp);
}

TEST_CASE("operations name the problem when refused, and the alias is programmed into the SII", "[hotconnect][segment]") {
    HotConnectBench bench(grouped());
    bench.with_segment([](sim::Segment& s) { REQUIRE(s.set_group_power(2, false)); });
    bench.start();
    auto port = bench.hot_connect->set_port(4711, 1, hotconnect::LoopSetting::Closed);
    REQUIRE_FALSE(port);
    CHECK(port.error().code == hotconnect::OperationError::NotFound);
    port = bench.hot_connect->set_port(2201, 1, hotconnect::LoopSetting::Closed);
    REQUIRE_FALSE(port);
    CHECK(port.error().code == hotconnect::OperationError::SlaveNotPresent);
    port = bench.hot_connect->set_port(1001, 0, hotconnect::LoopSetting::Closed);
    REQUIRE_FALSE(port);
    CHECK(port.error().code == hotconnect::OperationError::InvalidParam);
    CHECK(bench.hot_connect->block_node(std::nullopt, std::nullopt).error().code == hotconnect::OperationError::NotFound);

    const auto alias = bench.hot_connect->set_alias(2101, 0x1234);
    INFO((alias ? std::string() : alias.error().message));
    REQUIRE(alias);
    CHECK(*alias == 101);
    bench.with_segment([](sim::Segment& s) {
        const auto& sii = s.slave(2).sii_image();
        CHECK(load_le<std::uint16_t>(sii, 8) == 0x1234);
        REQUIRE(s.power_off(2));
        REQUIRE(s.power_on(2));
        CHECK(s.slave(2).station_alias() == 0x1234);  // the checksum is right: the slave loaded it
    });

    bench.hot_connect->set_active(false);
    CHECK(bench.hot_connect->accept().error().code == hotconnect::OperationError::MasterRedStateInactive);
}

}  // namespace
}  // namespace ecpair::test
