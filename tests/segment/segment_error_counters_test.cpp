// The ESC error counters 0x0300-0x0313 as the segment makes them count:
// frames damaged at one port (`port-errors`) or on a master's cable (an
// impairment) are counted as invalid frames and RX errors at the port that
// received them damaged and as forwarded RX errors at every port after it,
// never reach the master, saturate at 0xFF and are cleared by a write to
// their group; a lost link is counted at both ends of a cut cable.

#include <catch2/catch.hpp>

#include "ecpair/sim/control_commands.hpp"
#include "ecpair/sim/segment.hpp"
#include "segment_fixtures.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

constexpr std::uint32_t kBrdAlStatus = DatagramHeader::physical(0, 0x0130);

// 0x0300-0x0313 of one slave, as named registers.
struct Counters {
    std::array<std::uint8_t, 4> invalid{};
    std::array<std::uint8_t, 4> rx{};
    std::array<std::uint8_t, 4> forwarded{};
    std::uint8_t processing_unit = 0;
    std::array<std::uint8_t, 4> lost_link{};
};

Counters counters_of(const Segment& segment, std::size_t position) {
    const auto raw = segment.slave(position).read_memory(0x0300, 0x14);
    Counters c;
    for (std::size_t p = 0; p < 4; ++p) {
        c.invalid[p] = raw[2 * p];
        c.rx[p] = raw[2 * p + 1];
        c.forwarded[p] = raw[8 + p];
        c.lost_link[p] = raw[0x10 + p];
    }
    c.processing_unit = raw[0x0C];
    return c;
}

TestFrame brd() { return single(Command::Brd, kBrdAlStatus, 2); }

}  // namespace

TEST_CASE("a frame damaged at one port is counted there, as forwarded after it, and lost to the master",
          "[segment][error-counters]") {
    Segment segment = line_segment(5);
    REQUIRE(segment.inject_rx_errors(3, 0, 1));

    TestFrame damaged = brd();
    CHECK_FALSE(carry(segment, Side::Main, damaged));  // came round damaged: the NIC drops it
    CHECK(segment.counters().damaged_dropped == 1);
    CHECK(segment.counters().sides[static_cast<std::size_t>(Side::Red)].frames_out == 0);

    for (const std::size_t before : {1u, 2u}) {
        const Counters c = counters_of(segment, before);
        CHECK(c.invalid == std::array<std::uint8_t, 4>{});
        CHECK(c.forwarded == std::array<std::uint8_t, 4>{});
    }
    const Counters at = counters_of(segment, 3);
    CHECK(at.invalid[0] == 1);
    CHECK(at.rx[0] == 1);
    CHECK(at.forwarded[0] == 0);
    for (const std::size_t after : {4u, 5u}) {
        const Counters c = counters_of(segment, after);
        INFO("slave " << after);
        CHECK(c.forwarded[0] == 1);
        CHECK(c.invalid[0] == 0);
        CHECK(c.rx[0] == 0);
    }

    // The error is used up: the next frame goes round whole, processed by every slave.
    TestFrame whole = brd();
    CHECK(carry(segment, Side::Main, whole) == Side::Red);
    CHECK(wkc_of(whole) == 5);
    CHECK(counters_of(segment, 3).invalid[0] == 1);
}

TEST_CASE("a damaged frame changes nothing in the slaves it passes", "[segment][error-counters]") {
    Segment segment = line_segment(3);
    REQUIRE(segment.inject_rx_errors(2, 0, 1));
    // Station addresses by position: slave 1 takes it, slaves 2 and 3 get the damaged frame.
    TestFrame write = ethercat_frame({DatagramSpec{Command::Bwr, DatagramHeader::physical(0, 0x0010), {0x34, 0x12}}});
    CHECK_FALSE(carry(segment, Side::Main, write));
    CHECK(segment.slave(1).station_address() == 0x1234);
    CHECK(segment.slave(2).station_address() == 0);
    CHECK(segment.slave(3).station_address() == 0);
}

TEST_CASE("port errors count at the port the frame arrives by, whichever way it travels",
          "[segment][error-counters]") {
    Segment segment = line_segment(4);
    // Frames from RED enter each slave at port B (and pass it unprocessed in a closed ring).
    REQUIRE(segment.inject_rx_errors(3, 1, 2));
    TestFrame from_main = brd();
    CHECK(carry(segment, Side::Main, from_main) == Side::Red);  // port A of slave 3: untouched
    CHECK(counters_of(segment, 3).invalid == std::array<std::uint8_t, 4>{});

    for (int n = 0; n < 2; ++n) {
        TestFrame from_red = brd();
        CHECK_FALSE(carry(segment, Side::Red, from_red));
    }
    CHECK(counters_of(segment, 4).forwarded == std::array<std::uint8_t, 4>{});  // before the damage
    CHECK(counters_of(segment, 3).invalid[1] == 2);
    CHECK(counters_of(segment, 3).rx[1] == 2);
    CHECK(counters_of(segment, 2).forwarded[1] == 2);
    CHECK(counters_of(segment, 1).forwarded[1] == 2);
    CHECK(segment.counters().damaged_dropped == 2);
}

TEST_CASE("error counters stop at 0xFF and a write clears its group", "[segment][error-counters]") {
    Segment segment = line_segment(3);
    REQUIRE(segment.inject_rx_errors(2, 0, 300));
    for (int n = 0; n < 300; ++n) {
        TestFrame frame = brd();
        CHECK_FALSE(carry(segment, Side::Main, frame));
    }
    CHECK(counters_of(segment, 2).invalid[0] == 0xFF);
    CHECK(counters_of(segment, 2).rx[0] == 0xFF);
    CHECK(counters_of(segment, 3).forwarded[0] == 0xFF);

    REQUIRE(segment.break_link_after(2));
    REQUIRE(segment.repair_link_after(2));
    CHECK(counters_of(segment, 2).lost_link[1] == 1);  // both ends of the cut cable
    CHECK(counters_of(segment, 3).lost_link[0] == 1);

    // A write to any RX error counter clears 0x0300-0x030B (the datasheet; 0x030C apart); the lost links stay.
    TestFrame clear_rx = ethercat_frame({DatagramSpec{Command::Bwr, DatagramHeader::physical(0, 0x0309), {0}}});
    REQUIRE(carry(segment, Side::Main, clear_rx) == Side::Red);
    CHECK(wkc_of(clear_rx) == 3);
    for (const std::size_t position : {1u, 2u, 3u}) {
        const Counters c = counters_of(segment, position);
        CHECK(c.invalid == std::array<std::uint8_t, 4>{});
        CHECK(c.rx == std::array<std::uint8_t, 4>{});
        CHECK(c.forwarded == std::array<std::uint8_t, 4>{});
    }
    CHECK(counters_of(segment, 3).lost_link[0] == 1);
    TestFrame clear_lost = ethercat_frame({DatagramSpec{Command::Bwr, DatagramHeader::physical(0, 0x0310), {0}}});
    REQUIRE(carry(segment, Side::Main, clear_lost) == Side::Red);
    CHECK(counters_of(segment, 3).lost_link == std::array<std::uint8_t, 4>{});
    CHECK(counters_of(segment, 2).lost_link == std::array<std::uint8_t, 4>{});
}

TEST_CASE("a frame damaged on a master's cable is counted by the first port it reaches", "[segment][error-counters]") {
    Segment segment = line_segment(3);
    TestFrame from_main = brd();
    CHECK_FALSE(segment.carry(Side::Main, from_main.buffer, from_main.size, 1'000'000, FrameCondition::Damaged));
    CHECK(counters_of(segment, 1).invalid[0] == 1);
    CHECK(counters_of(segment, 2).forwarded[0] == 1);
    CHECK(counters_of(segment, 3).forwarded[0] == 1);

    TestFrame from_red = brd();
    CHECK_FALSE(segment.carry(Side::Red, from_red.buffer, from_red.size, 1'000'000, FrameCondition::Damaged));
    CHECK(counters_of(segment, 3).invalid[1] == 1);
    CHECK(counters_of(segment, 2).forwarded[1] == 1);
    CHECK(counters_of(segment, 1).forwarded[1] == 1);
    CHECK(segment.counters().damaged_dropped == 2);
}

TEST_CASE("port-errors over the control protocol", "[segment][error-counters][control]") {
    Segment segment = line_segment(3);
    CHECK(handle_control_line(segment, "port-errors 2 A 4") ==
          "ok the next 4 frame(s) arriving at slave 2 port A are damaged there");
    CHECK(segment.slave(2).rx_errors_pending(0) == 4);
    CHECK(handle_control_line(segment, "port-errors 2 0 1") ==
          "ok the next 1 frame(s) arriving at slave 2 port A are damaged there");
    CHECK(segment.slave(2).rx_errors_pending(0) == 5);
    CHECK(handle_control_line(segment, "port-errors 2 C 1") == "error: slave 2 'S2' has no port C (its ports: A, B)");
    CHECK(handle_control_line(segment, "port-errors 4 A 1") == "error: position 4 is out of range 1..3");
    CHECK(handle_control_line(segment, "port-errors 1 A 0") ==
          "error: port-errors: N must be a decimal number in 1..1000000, got '0'");
    CHECK(handle_control_line(segment, "port-errors 1 E 1") ==
          "error: port-errors: PORT must be A, B, C or D (or 0..3), got 'E'");
    CHECK(handle_control_line(segment, "port-errors 1 A") ==
          "error: port-errors takes 3 arguments, got 2: port-errors K PORT N");

    for (int n = 0; n < 5; ++n) {
        TestFrame frame = brd();
        CHECK_FALSE(carry(segment, Side::Main, frame));
    }
    CHECK(counters_of(segment, 2).invalid[0] == 5);
    CHECK_THAT(handle_control_line(segment, "status"), Catch::Contains("damaged_dropped=5 "));
    TestFrame whole = brd();
    CHECK(carry(segment, Side::Main, whole) == Side::Red);
}
