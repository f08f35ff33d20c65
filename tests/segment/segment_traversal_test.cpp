// How frames travel through a segment: the closed ring, the reverse
// direction, trees, padding, non-EtherCAT frames, the circulating bit and
// DC receive times, with real emulated ESCs.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/wire/source_mac.hpp"
#include "segment_fixtures.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

// Auto-increment address of the k-th slave in processing order (k = 0, 1, ...).
std::uint16_t position_adp(std::size_t k) { return static_cast<std::uint16_t>(0x10000 - k); }

std::vector<std::uint8_t> le16(std::uint16_t value) {
    return {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8)};
}

// Gives the slaves station addresses 0x0100, 0x0101, ... in the order the
// frame reaches them (one APWR per slave, all in one frame from MAIN).
std::optional<Side> assign_addresses_in_processing_order(Segment& segment, std::size_t count) {
    std::vector<DatagramSpec> datagrams;
    for (std::size_t k = 0; k < count; ++k) {
        datagrams.push_back(DatagramSpec{Command::Apwr, DatagramHeader::physical(position_adp(k), 0x0010),
                                         le16(static_cast<std::uint16_t>(0x0100 + k))});
    }
    TestFrame frame = ethercat_frame(datagrams);
    const auto exit = carry(segment, Side::Main, frame);
    for (std::size_t k = 0; k < count; ++k) CHECK(wkc_of(frame, k) == 1);
    return exit;
}

}  // namespace

TEST_CASE("a BRD from MAIN through the closed ring leaves at RED, processed by every slave", "[segment]") {
    Segment segment = line_segment(5);
    TestFrame frame = single(Command::Brd, DatagramHeader::physical(0, 0x0000), 2);
    REQUIRE(carry(segment, Side::Main, frame) == Side::Red);
    CHECK(wkc_of(frame) == 5);
    CHECK(header_of(frame).adp() == 5);  // every slave incremented it
    CHECK_FALSE(header_of(frame).circulating);
    CHECK(wire::SourceMac::decode(source_of(frame)).slave_forwarded);

    const auto& counters = segment.counters();
    CHECK(counters.sides[0].frames_in == 1);
    CHECK(counters.sides[1].frames_out == 1);
}

TEST_CASE("a frame entering at RED leaves at MAIN unprocessed", "[segment]") {
    Segment segment = line_segment(5);
    TestFrame frame = single(Command::Brd, DatagramHeader::physical(0, 0x0000), 2);
    const TestFrame sent = frame;
    REQUIRE(carry(segment, Side::Red, frame) == Side::Main);
    CHECK(wkc_of(frame) == 0);
    CHECK(header_of(frame).adp() == 0);
    CHECK(frame.size == sent.size);
    CHECK(std::equal(frame.buffer.begin(), frame.buffer.begin() + static_cast<std::ptrdiff_t>(frame.size),
                     sent.buffer.begin()));
}

TEST_CASE("a segment built from a real ENI carries frames around its ring", "[segment][eni]") {
    const auto config = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml"));
    REQUIRE(config);
    auto segment = Segment::from_eni(**config);
    REQUIRE(segment);
    REQUIRE(segment->slave_count() == 5);
    for (std::size_t p = 1; p <= 5; ++p) {
        CHECK(segment->slave(p).description().vendor_id == (*config)->slaves[p - 1].info.vendor_id);
    }
    TestFrame frame = single(Command::Brd, DatagramHeader::physical(0, 0x0130), 2);
    REQUIRE(carry(*segment, Side::Main, frame) == Side::Red);
    CHECK(wkc_of(frame) == 5);
}

TEST_CASE("a segment with no slaves is a cable from MAIN to RED", "[segment]") {
    auto segment = Segment::from_specs({});
    REQUIRE(segment);
    TestFrame frame = single(Command::Brd, 0, 2);
    CHECK(carry(*segment, Side::Main, frame) == Side::Red);
    CHECK(carry(*segment, Side::Red, frame) == Side::Main);
    CHECK(wkc_of(frame) == 0);
}

TEST_CASE("a short frame is padded with zeros to 60 bytes on entry", "[segment]") {
    Segment segment = line_segment(5);
    // SOEM's first frame: a 1-byte BRD, 29 bytes on a veth that does not pad.
    TestFrame frame = ethercat_frame({DatagramSpec{Command::Brd, 0, {0x00}}}, /*unpadded=*/true);
    REQUIRE(frame.size == 29);
    REQUIRE(frame.buffer[29] == 0xEE);  // stale bytes after the frame
    REQUIRE(carry(segment, Side::Main, frame) == Side::Red);
    CHECK(frame.size == 60);
    for (std::size_t i = 29; i < 60; ++i) CHECK(frame.buffer[i] == 0);
    CHECK(wkc_of(frame) == 5);
}

TEST_CASE("PreviousPort wiring sets the order in which a tree is processed", "[segment]") {
    SECTION("a 3-port coupler with a branch on port C") {
        // Coupler ports A, B, C: order 0 -> EPU -> 1 -> 2 -> 0. The line goes on at B,
        // the branch hangs on C and carries the RED side at its end.
        std::vector<SlaveSpec> specs{
            {test_slave("coupler", "YYY"), 1001, std::nullopt, 0},
            {test_slave("line 1"), 1002, eni::PreviousPort{true, 'B', 1001}, 0},
            {test_slave("line 2"), 1003, std::nullopt, 0},
            {test_slave("branch"), 1004, eni::PreviousPort{true, 'C', 1001}, 0},
        };
        auto segment = Segment::from_specs(std::move(specs));
        REQUIRE(segment);
        REQUIRE(assign_addresses_in_processing_order(*segment, 4) == Side::Red);
        for (std::size_t p = 1; p <= 4; ++p) CHECK(segment->slave(p).station_address() == 0x0100 + (p - 1));

        // From RED the frame runs the tree backwards and leaves at MAIN, unprocessed.
        TestFrame back = single(Command::Brd, 0, 2);
        REQUIRE(carry(*segment, Side::Red, back) == Side::Main);
        CHECK(wkc_of(back) == 0);
    }
    // A 4-port coupler; ESC order after its EPU is port D, then B, then C.
    SECTION("file order = processing order") {
        std::vector<SlaveSpec> specs{
            {test_slave("coupler", "YYYY"), 1001, std::nullopt, 0},
            {test_slave("on D"), 1002, eni::PreviousPort{true, 'D', 1001}, 0},
            {test_slave("on B"), 1003, eni::PreviousPort{true, 'B', 1001}, 0},
            {test_slave("on C"), 1004, eni::PreviousPort{true, 'C', 1001}, 0},
        };
        auto segment = Segment::from_specs(std::move(specs));
        REQUIRE(segment);
        REQUIRE(assign_addresses_in_processing_order(*segment, 4) == Side::Red);
        for (std::size_t p = 1; p <= 4; ++p) CHECK(segment->slave(p).station_address() == 0x0100 + (p - 1));
    }
    SECTION("the wiring, not the file order, decides") {
        std::vector<SlaveSpec> specs{
            {test_slave("coupler", "YYYY"), 1001, std::nullopt, 0},
            {test_slave("on B"), 1002, eni::PreviousPort{true, 'B', 1001}, 0},
            {test_slave("on D"), 1003, eni::PreviousPort{true, 'D', 1001}, 0},
            {test_slave("on C"), 1004, eni::PreviousPort{true, 'C', 1001}, 0},
        };
        auto segment = Segment::from_specs(std::move(specs));
        REQUIRE(segment);
        REQUIRE(assign_addresses_in_processing_order(*segment, 4) == Side::Red);
        CHECK(segment->slave(1).station_address() == 0x0100);
        CHECK(segment->slave(3).station_address() == 0x0101);  // on D comes first
        CHECK(segment->slave(2).station_address() == 0x0102);
        CHECK(segment->slave(4).station_address() == 0x0103);
    }
}

TEST_CASE("non-EtherCAT frames die at the first EPU unless its forwarding rule is off", "[segment]") {
    Segment segment = line_segment(5);
    TestFrame ip = non_ethercat_frame();
    CHECK_FALSE(carry(segment, Side::Main, ip));
    CHECK(segment.counters().non_ethercat_dropped == 1);

    // DL control 0x0100 bit 0 = 0 in every slave: forward non-EtherCAT frames.
    REQUIRE(send(segment, Side::Main, Side::Red, Command::Bwr, DatagramHeader::physical(0, 0x0100), {0x00}));
    TestFrame again = non_ethercat_frame();
    const TestFrame sent = again;
    CHECK(carry(segment, Side::Main, again) == Side::Red);
    CHECK(std::equal(again.buffer.begin(), again.buffer.begin() + 60, sent.buffer.begin()));
    CHECK(segment.counters().non_ethercat_dropped == 1);
}

TEST_CASE("an EtherCAT frame the EPUs cannot parse travels on untouched", "[segment]") {
    Segment segment = line_segment(3);
    TestFrame frame = single(Command::Brd, 0, 2);
    frame.buffer[wire::kEthernetHeaderSize + 1] = 0x50;  // EtherCAT header type 5 (mailbox gateway)
    const TestFrame sent = frame;
    CHECK(carry(segment, Side::Main, frame) == Side::Red);
    CHECK(std::equal(frame.buffer.begin(), frame.buffer.begin() + 60, sent.buffer.begin()));
    CHECK(segment.counters().unprocessable == 1);
}

TEST_CASE("a frame passing a closed port 0 gets the circulating bit, at the second one it dies", "[segment]") {
    // Mis-wired cables: slave 3 is reached through its port B, so its port A
    // is unconnected (auto-closed).
    std::vector<EscDescription> slaves{test_slave("S1"), test_slave("S2"), test_slave("S3", "YYYY")};
    std::vector<Cable> cables{
        Cable{Endpoint::of_side(Side::Main), Endpoint::of_port(0, 0), true},
        Cable{Endpoint::of_port(0, 1), Endpoint::of_port(1, 0), true},
        Cable{Endpoint::of_port(1, 1), Endpoint::of_port(2, 1), true},
    };
    SECTION("one closed port 0 on the way: the frame returns with C=1") {
        auto segment = Segment::with_wiring(slaves, cables);
        REQUIRE(segment);
        TestFrame frame = single(Command::Brd, 0, 2);
        REQUIRE(carry(*segment, Side::Main, frame) == Side::Main);
        CHECK(header_of(frame).circulating);
        CHECK(wkc_of(frame) == 3);
    }
    SECTION("two closed ports 0 on the way: the second EPU destroys it") {
        // Slave 4 hangs on slave 3's port D by its port B: its port A is unconnected too.
        slaves.push_back(test_slave("S4"));
        cables.push_back(Cable{Endpoint::of_port(2, 3), Endpoint::of_port(3, 1), true});
        auto segment = Segment::with_wiring(slaves, cables);
        REQUIRE(segment);
        TestFrame frame = single(Command::Brd, 0, 2);
        CHECK_FALSE(carry(*segment, Side::Main, frame));
        CHECK(segment->counters().destroyed_circulating == 1);
        CHECK(segment->counters().sides[0].frames_out == 0);
    }
}

TEST_CASE("each ESC and cable on the way add their delays to the DC receive times", "[segment][dc]") {
    SegmentOptions options;
    options.propagation = {0, 250, 250};
    options.clocks.seed = 0;  // exact clocks: the latches show the simulation time
    auto segment = Segment::from_specs(line_specs(4), options);
    REQUIRE(segment);
    // A write to 0x0900 latches every slave's port receive times.
    TestFrame latch = single(Command::Bwr, DatagramHeader::physical(0, 0x0900), 4);
    REQUIRE(carry(*segment, Side::Main, latch, 5'000'000) == Side::Red);
    std::vector<std::uint32_t> port0_times;
    for (std::size_t p = 1; p <= 4; ++p) {
        const auto bytes = segment->slave(p).read_memory(0x0900, 4);
        port0_times.push_back(load_le<std::uint32_t>(bytes));
    }
    for (std::size_t i = 1; i < port0_times.size(); ++i) CHECK(port0_times[i] - port0_times[i - 1] == 250);
}
