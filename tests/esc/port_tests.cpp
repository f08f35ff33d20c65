// Ports, loop control and the frame-level rules of the processing unit:
// DL status, loop settings, auto-close, recovery port, circulating frames,
// the source MAC bit, non-EtherCAT frames, lost-link and error counters.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::uint16_t dl_status(Line& line, std::uint16_t station) {
    const auto raw = line.fprd(station, 0x0110, 2);
    return static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
}

Frame nop_frame() { return Frame({physical(Command::Nop, 0, 0, bytes({0}))}); }

}  // namespace

TEST_CASE("DL status: 0x5A for a middle slave, 0x56 for the last, 0x55 with every port closed") {
    Line line({drive_description("first"), drive_description("middle"), drive_description("last")});
    line.assign_station_addresses();
    CHECK(dl_status(line, 0x1001) == 0x5A33);
    CHECK(dl_status(line, 0x1002) == 0x5A33);
    CHECK(dl_status(line, 0x1003) == 0x5613);  // no link on port 1

    Esc lonely(drive_description());
    CHECK(lonely.read_memory(0x0110, 2) == bytes({0x03, 0x55}));
    CHECK(lonely.port_open(0));  // the recovery port
    CHECK_FALSE(lonely.port_open(1));
}

TEST_CASE("ports open and close with the link under Auto - not implemented ports stay closed") {
    Esc esc(coupler_description());
    CHECK(esc.port_count() == 3);
    CHECK(esc.port_implemented(2));
    CHECK_FALSE(esc.port_implemented(3));
    esc.set_physical_link(0, true);
    esc.set_physical_link(2, true);
    CHECK(esc.port_open(0));
    CHECK_FALSE(esc.port_open(1));
    CHECK(esc.port_open(2));
    CHECK_FALSE(esc.port_open(3));
    esc.set_physical_link(3, true);  // nothing there
    CHECK_FALSE(esc.physical_link(3));
    CHECK_FALSE(esc.port_open(3));
    esc.set_physical_link(2, false);
    CHECK_FALSE(esc.port_open(2));
}

TEST_CASE("loop settings from 0x0101 take effect at the end of the frame") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    REQUIRE(line[0].port_open(1));
    Frame frame({physical(Command::Fpwr, 0x1001, 0x0101, bytes({0x0C})), physical_read(Command::Fprd, 0x1001, 0x0101, 1)});
    line.run(frame);
    CHECK(frame.datagram(1).data == bytes({0x00}));  // still the old setting within the frame
    CHECK(line[0].loop_setting(1) == LoopSetting::Closed);
    CHECK_FALSE(line[0].port_open(1));
    CHECK(dl_status(line, 0x1001) == 0x5E33);  // port 1 closed, communication established

    line.fpwr(0x1001, 0x0101, bytes({0x08}));  // port 1 manually open
    CHECK(line[0].loop_setting(1) == LoopSetting::Open);
    line[0].set_physical_link(1, false);
    CHECK(line[0].port_open(1));  // open regardless of the link
}

TEST_CASE("auto-close: closes on link loss and waits to be reopened") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line.fpwr(0x1001, 0x0101, bytes({0x04}));  // port 1 auto-close
    REQUIRE(line[0].loop_setting(1) == LoopSetting::AutoClose);
    CHECK(line[0].port_open(1));

    line[0].set_physical_link(1, false);
    CHECK_FALSE(line[0].port_open(1));
    line[0].set_physical_link(1, true);
    CHECK_FALSE(line[0].port_open(1));  // closed wait

    SECTION("a valid frame received on the port reopens it") {
        line[0].frame_arrived_at_port(1, line.time_ns(), 999);
        CHECK(line[0].port_open(1));
    }
    SECTION("the master writing the loop setting again (through port 0) reopens it") {
        line.fpwr(0x1001, 0x0100, bytes({0x01, 0x04}));
        CHECK(line[0].port_open(1));
    }
    SECTION("a frame without a loop setting write does not") {
        Frame nop = nop_frame();
        line.run(nop);
        CHECK_FALSE(line[0].port_open(1));
    }
}

TEST_CASE("temporary loop settings revert after about a second") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line.fpwr(0x1001, 0x0100, bytes({0x03, 0x0C}));  // temporary, port 1 closed
    CHECK_FALSE(line[0].port_open(1));
    line.advance(500'000'000);
    line.fprd(0x1001, 0x0000, 1);
    CHECK_FALSE(line[0].port_open(1));
    line.advance(600'000'000);
    line.fprd(0x1001, 0x0000, 1);
    CHECK(line[0].port_open(1));
    CHECK(line.fprd(0x1001, 0x0100, 2) == bytes({0x01, 0x00}));
}

TEST_CASE("circulating frames: marked at a closed port 0, destroyed on the second pass") {
    Esc esc(drive_description());  // no link on port 0: closed under Auto
    esc.set_physical_link(1, true);
    REQUIRE(esc.port_open(1));
    Frame frame({physical_read(Command::Brd, 0, 0x0000, 1), physical_read(Command::Brd, 0, 0x0000, 1)});
    auto view = frame.view();
    CHECK(esc.process(view, FrameContext{1000, 1}) == EpuVerdict::Forward);
    CHECK(frame.datagram(0).circulating);
    CHECK(frame.datagram(1).circulating);
    CHECK(frame.datagram(0).wkc == 1);  // processed
    CHECK(esc.read_memory(0x030C, 1) == bytes({0}));

    auto again = frame.view();
    CHECK(esc.process(again, FrameContext{2000, 1}) == EpuVerdict::Destroy);
    CHECK(frame.datagram(0).wkc == 1);  // not processed
    CHECK(esc.read_memory(0x030C, 1) == bytes({1}));

    // With port 0 manually closed the rule does not apply.
    Frame close_port0({physical(Command::Bwr, 0, 0x0101, bytes({0x03}))});
    auto close_view = close_port0.view();
    CHECK(esc.process(close_view, FrameContext{3000, 2}) == EpuVerdict::Forward);
    REQUIRE(esc.loop_setting(0) == LoopSetting::Closed);
    Frame other({physical_read(Command::Brd, 0, 0x0000, 1)});
    auto other_view = other.view();
    CHECK(esc.process(other_view, FrameContext{4000, 3}) == EpuVerdict::Forward);
    CHECK_FALSE(other.datagram(0).circulating);
    CHECK(esc.read_memory(0x030C, 1) == bytes({1}));
}

TEST_CASE("the processing unit sets the source MAC's locally administered bit while the forwarding rule is on") {
    Line line({drive_description()});
    line.assign_station_addresses();
    Frame frame({physical_read(Command::Brd, 0, 0, 1)}, wire::MacAddress{{0x01, 0x01, 0x01, 0x01, 0x01, 0x01}});
    line.run(frame);
    CHECK(frame.source() == wire::MacAddress{{0x03, 0x01, 0x01, 0x01, 0x01, 0x01}});
    CHECK(line[0].process_non_ethercat() == EpuVerdict::Destroy);

    line.fpwr(0x1001, 0x0100, bytes({0x00}));  // forwarding rule off (as SOEM does for slaves 2..n)
    Frame plain({physical_read(Command::Brd, 0, 0, 1)}, wire::MacAddress{{0x00, 0x11, 0x22, 0x33, 0x44, 0x55}});
    line.run(plain);
    CHECK(plain.source() == wire::MacAddress{{0x00, 0x11, 0x22, 0x33, 0x44, 0x55}});
    CHECK(line[0].process_non_ethercat() == EpuVerdict::Forward);
}

TEST_CASE("lost links of open Auto ports are counted - writing a counter clears its group") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line[0].set_physical_link(1, false);
    line[0].set_physical_link(1, true);
    line[0].set_physical_link(1, false);
    CHECK(line.fprd(0x1001, 0x0310, 4) == bytes({0, 2, 0, 0}));
    CHECK(line.fpwr(0x1001, 0x0313, bytes({0})) == 1);
    CHECK(line.fprd(0x1001, 0x0310, 4) == bytes({0, 0, 0, 0}));

    line[0].write_memory(0x0300, bytes({5, 6, 7, 8}));
    line[0].write_memory(0x030C, bytes({9}));
    CHECK(line.fpwr(0x1001, 0x0300, bytes({0})) == 1);
    CHECK(line.fprd(0x1001, 0x0300, 13) == bytes({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 9}));
    CHECK(line.fpwr(0x1001, 0x030C, bytes({0})) == 1);
    CHECK(line.fprd(0x1001, 0x030C, 1) == bytes({0}));
}
