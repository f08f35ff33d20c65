// Faults on a simulated segment: line breaks everywhere, power, the master
// sides' carrier, auto-close's closed wait after a repair, unknown slaves,
// EEPROM alias and ID selector, and the refusals.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sim/segment.hpp"
#include "segment_fixtures.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

constexpr std::uint32_t kBrdAlStatus = DatagramHeader::physical(0, 0x0130);
// DL control byte 0x0101: loop setting 01 (auto-close) for ports 0..3.
constexpr std::uint8_t kAllAutoClose = 0x55;

std::uint16_t position_adp(std::size_t position) { return static_cast<std::uint16_t>(0x10000 - (position - 1)); }

std::string refusal(const Expected<void, FaultError>& result) {
    REQUIRE_FALSE(result);
    return result.error().message;
}

}  // namespace

TEST_CASE("a line break after slave k splits the ring into two halves", "[segment][faults]") {
    const std::size_t n = 5;
    const std::size_t k = GENERATE(as<std::size_t>{}, 0, 1, 2, 3, 4, 5);
    Segment segment = line_segment(n);
    REQUIRE(segment.break_link_after(k));
    CHECK_FALSE(segment.link_after_intact(k));

    TestFrame from_main = single(Command::Brd, kBrdAlStatus, 2);
    const auto main_exit = carry(segment, Side::Main, from_main);
    TestFrame from_red = single(Command::Brd, kBrdAlStatus, 2);
    const auto red_exit = carry(segment, Side::Red, from_red);

    std::uint16_t total = 0;
    if (k == 0) {
        CHECK_FALSE(main_exit);  // the MAIN cable itself is cut
    } else {
        REQUIRE(main_exit == Side::Main);
        CHECK(wkc_of(from_main) == k);
        CHECK_FALSE(header_of(from_main).circulating);  // slave 1's port 0 is open
        total = static_cast<std::uint16_t>(total + wkc_of(from_main));
    }
    if (k == n) {
        CHECK_FALSE(red_exit);  // the RED cable itself is cut
    } else {
        REQUIRE(red_exit == Side::Red);
        CHECK(wkc_of(from_red) == n - k);
        CHECK(header_of(from_red).circulating);  // slave k+1 has port 0 closed
        total = static_cast<std::uint16_t>(total + wkc_of(from_red));
    }
    CHECK(total == n);
    CHECK(segment.counters().lost_no_link == ((k == 0 || k == n) ? 1u : 0u));

    REQUIRE(segment.repair_link_after(k));
    TestFrame healed = single(Command::Brd, kBrdAlStatus, 2);
    REQUIRE(carry(segment, Side::Main, healed) == Side::Red);
    CHECK(wkc_of(healed) == n);
}

TEST_CASE("a powered-off slave cuts the ring on both of its sides", "[segment][faults]") {
    Segment segment = line_segment(5);
    // Give slave 3 a station address, to see power-on reset it.
    REQUIRE(send(segment, Side::Main, Side::Red, Command::Apwr, DatagramHeader::physical(position_adp(3), 0x0010),
                 {0x03, 0x10}));
    REQUIRE(segment.slave(3).station_address() == 0x1003);

    REQUIRE(segment.power_off(3));
    CHECK_FALSE(segment.slave(3).powered());
    CHECK_FALSE(segment.slave(2).physical_link(1));
    CHECK_FALSE(segment.slave(4).physical_link(0));

    const auto main_return = send(segment, Side::Main, Side::Main, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(main_return);
    CHECK(wkc_of(*main_return) == 2);
    const auto red_return = send(segment, Side::Red, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(red_return);
    CHECK(wkc_of(*red_return) == 2);
    CHECK(header_of(*red_return).circulating);

    REQUIRE(segment.power_off(3));  // again: nothing changes
    REQUIRE(segment.power_on(3));
    CHECK(segment.slave(3).powered());
    CHECK(segment.slave(3).station_address() == 0);  // restarted from reset
    const auto healed = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(healed);
    CHECK(wkc_of(*healed) == 5);
}

TEST_CASE("a side without carrier: slave 1's port 0 closes, RED frames come back on RED", "[segment][faults]") {
    Segment segment = line_segment(5);
    segment.set_side_link(Side::Main, false);
    CHECK_FALSE(segment.side_link(Side::Main));
    CHECK_FALSE(segment.slave(1).physical_link(0));
    CHECK_FALSE(segment.slave(1).port_open(0));

    const auto red_return = send(segment, Side::Red, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(red_return);
    CHECK(wkc_of(*red_return) == 5);
    CHECK(header_of(*red_return).circulating);

    segment.set_side_link(Side::Main, true);
    CHECK(segment.slave(1).port_open(0));
    const auto main_return = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(main_return);
    CHECK(wkc_of(*main_return) == 5);
}

TEST_CASE("after a repair, auto-close ports wait closed until the ESC sees a reason to open", "[segment][faults]") {
    Segment segment = line_segment(5);

    SECTION("the master writes the loop setting again from both sides") {
        const auto configured =
            send(segment, Side::Main, Side::Red, Command::Bwr, DatagramHeader::physical(0, 0x0101), {kAllAutoClose});
        REQUIRE(configured);
        REQUIRE(wkc_of(*configured) == 5);

        REQUIRE(segment.break_link_after(2));
        REQUIRE(segment.repair_link_after(2));
        CHECK(segment.slave(2).physical_link(1));
        CHECK_FALSE(segment.slave(2).port_open(1));  // closed wait
        CHECK_FALSE(segment.slave(3).port_open(0));

        // Still two halves.
        const auto main_return = send(segment, Side::Main, Side::Main, Command::Brd, kBrdAlStatus, {0, 0});
        REQUIRE(main_return);
        CHECK(wkc_of(*main_return) == 2);
        const auto red_return = send(segment, Side::Red, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
        REQUIRE(red_return);
        CHECK(wkc_of(*red_return) == 3);

        // Rewriting 0x0101 through another port opens the waiting port.
        REQUIRE(
            send(segment, Side::Red, Side::Red, Command::Bwr, DatagramHeader::physical(0, 0x0101), {kAllAutoClose}));
        CHECK(segment.slave(3).port_open(0));
        REQUIRE(
            send(segment, Side::Main, Side::Main, Command::Bwr, DatagramHeader::physical(0, 0x0101), {kAllAutoClose}));
        CHECK(segment.slave(2).port_open(1));

        const auto ring = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
        REQUIRE(ring);
        CHECK(wkc_of(*ring) == 5);
        CHECK(segment.counters().lost_closed_port == 0);
    }

    SECTION("a frame arriving at the waiting port opens it, and is lost") {
        // Auto-close on slave 3 only; slave 2 stays in Auto.
        const auto configured = send(segment, Side::Main, Side::Red, Command::Apwr,
                                     DatagramHeader::physical(position_adp(3), 0x0101), {kAllAutoClose});
        REQUIRE(configured);
        REQUIRE(wkc_of(*configured) == 1);

        REQUIRE(segment.break_link_after(2));
        REQUIRE(segment.repair_link_after(2));
        CHECK(segment.slave(2).port_open(1));        // Auto: open with the link
        CHECK_FALSE(segment.slave(3).port_open(0));  // auto-close: closed wait

        TestFrame first = single(Command::Brd, kBrdAlStatus, 2);
        CHECK_FALSE(carry(segment, Side::Main, first));
        CHECK(segment.counters().lost_closed_port == 1);
        CHECK(segment.slave(3).port_open(0));

        const auto ring = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
        REQUIRE(ring);
        CHECK(wkc_of(*ring) == 5);
    }
}

TEST_CASE("an unknown slave spliced into the ring and taken out again", "[segment][faults]") {
    Segment segment = line_segment(5);
    REQUIRE(segment.insert_unknown_slave(3));
    REQUIRE(segment.slave_count() == 6);
    CHECK(segment.is_unknown(3));
    CHECK(segment.slave(3).description().vendor_id == kUnknownSlaveVendorId);
    CHECK(segment.slave(4).description().name == "S3");

    const auto ring = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(ring);
    CHECK(wkc_of(*ring) == 6);
    // Position addressing now finds the unknown slave at position 3.
    const auto vendor =
        send(segment, Side::Main, Side::Red, Command::Aprd, DatagramHeader::physical(position_adp(3), 0), {0, 0});
    REQUIRE(vendor);
    CHECK(wkc_of(*vendor) == 1);

    const auto refused = segment.remove_unknown_slave(2);
    REQUIRE_FALSE(refused);
    CHECK(refused.error().message ==
          "slave 2 is 'S2' from the ENI; only slaves added by insert-unknown, plug-unknown or plug-duplicate can be removed");

    REQUIRE(segment.remove_unknown_slave(3));
    REQUIRE(segment.slave_count() == 5);
    CHECK(segment.slave(3).description().name == "S3");
    const auto healed = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(healed);
    CHECK(wkc_of(*healed) == 5);
}

TEST_CASE("unknown slaves at both ends of the line", "[segment][faults]") {
    Segment segment = line_segment(2);
    REQUIRE(segment.insert_unknown_slave(1));
    REQUIRE(segment.insert_unknown_slave(4));
    CHECK(segment.is_unknown(1));
    CHECK(segment.is_unknown(4));
    const auto ring = send(segment, Side::Main, Side::Red, Command::Brd, kBrdAlStatus, {0, 0});
    REQUIRE(ring);
    CHECK(wkc_of(*ring) == 4);
    REQUIRE(segment.remove_unknown_slave(4));
    REQUIRE(segment.remove_unknown_slave(1));
    CHECK(segment.slave(1).description().name == "S1");
}

TEST_CASE("a new EEPROM alias is taken over at the next power-on", "[segment][faults]") {
    Segment segment = line_segment(3);
    REQUIRE(segment.set_eeprom_alias(2, 0x1234));
    REQUIRE(segment.power_off(2));
    REQUIRE(segment.power_on(2));
    CHECK(segment.slave(2).station_alias() == 0x1234);
    CHECK(segment.slave(1).station_alias() == 0);
}

TEST_CASE("the ID selector answers an explicit device ID request", "[segment][faults]") {
    Segment segment = line_segment(3);
    REQUIRE(segment.set_id_selector(2, 0x0042));
    // AL control: INIT with the device identification request bit (b5).
    REQUIRE(send(segment, Side::Main, Side::Red, Command::Apwr, DatagramHeader::physical(position_adp(2), 0x0120),
                 {0x21, 0x00}));
    CHECK(segment.slave(2).al_status_code() == 0x0042);
}

TEST_CASE("faults name what is out of range", "[segment][faults]") {
    Segment segment = line_segment(5);
    CHECK(refusal(segment.power_off(0)) == "position 0 is out of range 1..5");
    CHECK(refusal(segment.power_on(6)) == "position 6 is out of range 1..5");
    CHECK(refusal(segment.break_link_after(6)) == "link 6 is out of range 0..5");
    CHECK(refusal(segment.repair_link_after(7)) == "link 7 is out of range 0..5");
    CHECK(refusal(segment.insert_unknown_slave(7)) == "position 7 is out of range 1..6");
    CHECK(refusal(segment.set_eeprom_alias(9, 1)) == "position 9 is out of range 1..5");
    CHECK(refusal(segment.set_id_selector(0, 1)) == "position 0 is out of range 1..5");

    auto empty = Segment::from_specs({});
    REQUIRE(empty);
    CHECK(refusal(empty->power_off(1)) == "the segment has no slaves");
}

TEST_CASE("an ENI whose PreviousPort names a missing port is refused with file and line", "[segment][eni]") {
    const std::string xml = R"(<?xml version="1.0" encoding="ISO-8859-1"?>
<EtherCATConfig Version="1.3">
  <Config>
    <Master>
      <Info><Name>test master</Name><Destination>ffffffffffff</Destination><Source>000000000000</Source><EtherType>a488</EtherType></Info>
    </Master>
    <Slave>
      <Info><Name>first</Name><PhysAddr>1001</PhysAddr><AutoIncAddr>0</AutoIncAddr><Physics>YY</Physics>
        <VendorId>2</VendorId><ProductCode>1</ProductCode><RevisionNo>1</RevisionNo><SerialNo>0</SerialNo></Info>
    </Slave>
    <Slave>
      <Info><Name>second</Name><PhysAddr>1002</PhysAddr><AutoIncAddr>65535</AutoIncAddr><Physics>YY</Physics>
        <VendorId>2</VendorId><ProductCode>1</ProductCode><RevisionNo>1</RevisionNo><SerialNo>0</SerialNo></Info>
      <PreviousPort Selected="1"><Port>C</Port><PhysAddr>1001</PhysAddr></PreviousPort>
    </Slave>
    <Cyclic><Frame><Cmd><State>OP</State><Cmd>7</Cmd><Adp>0</Adp><Ado>304</Ado><DataLength>2</DataLength><Cnt>2</Cnt></Cmd></Frame></Cyclic>
  </Config>
</EtherCATConfig>
)";
    const auto config = eni::load_eni_string(xml, "bad-port.xml");
    REQUIRE(config);
    const auto segment = Segment::from_eni(**config);
    REQUIRE_FALSE(segment);
    CHECK(segment.error().file == "bad-port.xml");
    CHECK(segment.error().line == (*config)->slaves[1].source_line);
    CHECK(segment.error().describe() ==
          "bad-port.xml:" + std::to_string((*config)->slaves[1].source_line) +
              ": slave 2 'second' (PhysAddr 1002): its upstream port C of slave 1 'first' (PhysAddr 1001) does not "
              "exist (that slave has ports A, B)");
}
