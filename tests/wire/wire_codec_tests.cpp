// Frame and datagram codec: byte vectors checked by hand against
// esc-facts.md §1 (little-endian fields, Len word bits, 60-byte padding),
// round trips, and a located error for every kind of malformed frame.

#include <array>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

using namespace ecpair;
using namespace ecpair::wire;

namespace {

// BRD of AL status (ADO 0x0130), 2 bytes, from source 02:00:00:aa:bb:cc.
const std::vector<std::uint8_t> kBrdAlStatus = {
    0xff, 0xff, 0xff, 0xff, 0xff, 0xff,  // destination: broadcast
    0x02, 0x00, 0x00, 0xaa, 0xbb, 0xcc,  // source
    0x88, 0xa4,                          // EtherType 0x88A4 (big-endian on the wire)
    0x0e, 0x10,                          // EtherCAT header: length 14, type 1 -> 0x100E LE
    0x07, 0x05,                          // BRD, index 5
    0x00, 0x00, 0x30, 0x01,              // ADP 0, ADO 0x0130
    0x02, 0x00,                          // Len 2, C=0, M=0
    0x00, 0x00,                          // IRQ
    0x00, 0x00,                          // data
    0x00, 0x00,                          // WKC
};

EthernetHeader broadcast_from(std::array<std::uint8_t, 6> src) {
    EthernetHeader h;
    h.destination = MacAddress::broadcast();
    h.source.bytes = src;
    return h;
}

}  // namespace

TEST_CASE("a single BRD encodes to the hand-checked bytes and is padded to 60", "[wire]") {
    std::array<std::uint8_t, kMaxFrameSize> buffer{};
    FrameBuilder builder(buffer, broadcast_from({0x02, 0x00, 0x00, 0xaa, 0xbb, 0xcc}));
    DatagramHeader h;
    h.command = Command::Brd;
    h.index = 5;
    h.address = DatagramHeader::physical(0, 0x0130);
    REQUIRE(builder.append(h, 2));
    const auto frame = builder.finish();

    REQUIRE(frame.size() == kMinFrameSize);
    REQUIRE(std::vector<std::uint8_t>(frame.begin(), frame.begin() + 30) == kBrdAlStatus);
    for (std::size_t i = 30; i < frame.size(); ++i) CHECK(frame[i] == 0);
}

TEST_CASE("decoding the BRD gives back every field", "[wire]") {
    auto bytes = kBrdAlStatus;
    auto view = FrameView::parse(bytes);
    REQUIRE(view);
    CHECK(view->ethernet().ether_type == kEtherTypeEtherCat);
    CHECK(view->ecat_header().length == 14);
    CHECK(view->ecat_header().type == 1);
    REQUIRE(view->datagram_count() == 1);
    const auto d = *view->begin();
    const auto h = d.header();
    CHECK(h.command == Command::Brd);
    CHECK(h.index == 5);
    CHECK(h.adp() == 0);
    CHECK(h.ado() == 0x0130);
    CHECK(h.length == 2);
    CHECK_FALSE(h.more);
    CHECK_FALSE(h.circulating);
    CHECK(d.wkc() == 0);
    CHECK(d.frame_offset() == 16);
    CHECK(view->end_offset() == 30);
}

TEST_CASE("the Len word carries length, reserved, circulating and more bits", "[wire]") {
    DatagramHeader h;
    h.command = Command::Lrw;
    h.index = 0xab;
    h.address = 0x01000000;
    h.length = 0x07ff;
    h.reserved = 5;
    h.circulating = true;
    h.more = true;
    h.irq = 0x1234;
    std::array<std::uint8_t, kDatagramHeaderSize> out{};
    h.encode(out);
    const std::array<std::uint8_t, 10> expected = {0x0c, 0xab, 0x00, 0x00, 0x00, 0x01,
                                                   0xff, 0xef,  // 0x07ff | 5<<11 | 0x4000 | 0x8000
                                                   0x34, 0x12};
    CHECK(out == expected);
    CHECK(DatagramHeader::decode(out) == h);
}

TEST_CASE("several datagrams are chained with the M bit and iterate in order", "[wire]") {
    std::array<std::uint8_t, kMaxFrameSize> buffer{};
    FrameBuilder builder(buffer, broadcast_from({0x00, 0x01, 0x00, 0x11, 0x22, 0x33}));
    const std::array<std::uint8_t, 3> payload = {1, 2, 3};
    DatagramHeader a{Command::Aprd, 1, DatagramHeader::physical(0xffff, 0x0010), 0, 0, false, false, 0};
    DatagramHeader b{Command::Lrd, 2, 0x09000000, 0, 0, false, false, 0};
    DatagramHeader c{Command::Nop, 3, DatagramHeader::physical(0, 0x4155), 0, 0, false, false, 0};
    REQUIRE(builder.append(a, 2));
    REQUIRE(builder.append(b, payload));
    auto last = builder.append(c, 0);
    REQUIRE(last);
    last->set_wkc(7);
    auto frame = builder.finish();
    CHECK(builder.datagram_count() == 3);

    auto view = FrameView::parse(frame);
    REQUIRE(view);
    REQUIRE(view->datagram_count() == 3);
    CHECK(view->ecat_header().length == (12 + 2) + (12 + 3) + 12);
    std::vector<DatagramHeader> seen;
    for (auto d : *view) seen.push_back(d.header());
    REQUIRE(seen.size() == 3);
    CHECK(seen[0].command == Command::Aprd);
    CHECK(seen[0].more);
    CHECK(seen[0].adp() == 0xffff);
    CHECK(seen[1].command == Command::Lrd);
    CHECK(seen[1].more);
    CHECK(seen[1].address == 0x09000000u);
    CHECK(seen[2].command == Command::Nop);
    CHECK_FALSE(seen[2].more);
    auto it = view->begin();
    ++it;
    const auto lrd = *it;
    CHECK(std::vector<std::uint8_t>(lrd.data().begin(), lrd.data().end()) == std::vector<std::uint8_t>{1, 2, 3});
    CHECK((*++it).wkc() == 7);
}

TEST_CASE("datagram views change data, WKC, address, IRQ and C bit in place", "[wire]") {
    auto bytes = kBrdAlStatus;
    auto view = FrameView::parse(bytes);
    REQUIRE(view);
    auto d = *view->begin();
    d.data()[0] = 0x08;
    d.set_wkc(3);
    d.set_address(DatagramHeader::physical(3, 0x0130));
    d.set_irq(0x0004);
    d.set_circulating(true);
    CHECK(bytes[26] == 0x08);
    CHECK(bytes[28] == 3);
    CHECK(bytes[18] == 3);
    CHECK(bytes[24] == 0x04);
    CHECK(bytes[23] == 0x40);
    CHECK(d.header().circulating);
    d.set_circulating(false);
    CHECK(bytes[23] == 0x00);
}

TEST_CASE("a frame that does not fit refuses further datagrams", "[wire]") {
    std::array<std::uint8_t, kMaxFrameSize> buffer{};
    FrameBuilder builder(buffer, broadcast_from({0, 0, 0, 0, 0, 1}));
    CHECK(builder.remaining_data_capacity() == kMaxDatagramData);
    REQUIRE(builder.append(DatagramHeader{Command::Lwr, 0, 0, 0, 0, false, false, 0}, 1400));
    CHECK(builder.remaining_data_capacity() == kMaxEcatPayload - 1412 - kDatagramOverhead);
    CHECK_FALSE(builder.append(DatagramHeader{}, 100));
    CHECK(builder.append(DatagramHeader{}, builder.remaining_data_capacity()));
    CHECK(builder.finish().size() == kMaxFrameSize);
}

TEST_CASE("VLAN-tagged frames decode and keep their tag", "[wire]") {
    std::vector<std::uint8_t> bytes(kBrdAlStatus.begin(), kBrdAlStatus.begin() + 12);
    const std::uint8_t vlan_tag[] = {0x81, 0x00, 0x20, 0x07};
    bytes.insert(bytes.end(), std::begin(vlan_tag), std::end(vlan_tag));
    bytes.insert(bytes.end(), kBrdAlStatus.begin() + 12, kBrdAlStatus.end());
    auto view = FrameView::parse(bytes);
    REQUIRE(view);
    REQUIRE(view->ethernet().vlan_tci);
    CHECK(*view->ethernet().vlan_tci == 0x2007);
    CHECK(view->ecat_offset() == 18);
    CHECK((*view->begin()).header().ado() == 0x0130);
}

TEST_CASE("malformed frames give a typed error naming the offset", "[wire]") {
    SECTION("shorter than an Ethernet header") {
        std::vector<std::uint8_t> bytes(kBrdAlStatus.begin(), kBrdAlStatus.begin() + 10);
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::TruncatedEthernetHeader);
        CHECK(r.error().offset == 0);
    }
    SECTION("another EtherType") {
        auto bytes = kBrdAlStatus;
        bytes[12] = 0x08;
        bytes[13] = 0x00;
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::NotEtherCat);
        CHECK(r.error().offset == 12);
        CHECK(r.error().describe() == "not an EtherCAT frame (ether type 0x0800) at offset 12");
    }
    SECTION("cut inside the EtherCAT header") {
        std::vector<std::uint8_t> bytes(kBrdAlStatus.begin(), kBrdAlStatus.begin() + 15);
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::TruncatedEcatHeader);
        CHECK(r.error().offset == 14);
    }
    SECTION("EtherCAT type other than datagrams") {
        auto bytes = kBrdAlStatus;
        bytes[15] = 0x50;  // type 5 (mailbox gateway)
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::UnsupportedEcatType);
        CHECK(r.error().detail == 5);
    }
    SECTION("cut inside a datagram header") {
        std::vector<std::uint8_t> bytes(kBrdAlStatus.begin(), kBrdAlStatus.begin() + 20);
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::TruncatedDatagramHeader);
        CHECK(r.error().offset == 16);
    }
    SECTION("a Len that runs past the end") {
        auto bytes = kBrdAlStatus;
        bytes[22] = 0x40;  // Len 64, the frame has 2 data bytes
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::DatagramOverrun);
        CHECK(r.error().offset == 16);
        CHECK(r.error().detail == 64);
        CHECK(r.error().describe() ==
              "datagram runs past the end of the frame: datagram at offset 16 declares 64 data bytes");
    }
    SECTION("M set on the last datagram with nothing after it") {
        auto bytes = kBrdAlStatus;
        bytes[23] = 0x80;
        auto r = FrameView::parse(bytes);
        REQUIRE_FALSE(r);
        CHECK(r.error().code == DecodeErrc::TruncatedDatagramHeader);
        CHECK(r.error().offset == 30);
    }
}

TEST_CASE("the EtherCAT length is not trusted: datagrams are walked by their own Len", "[wire]") {
    auto bytes = kBrdAlStatus;
    bytes[14] = 0x00;  // header claims length 0
    auto view = FrameView::parse(bytes);
    REQUIRE(view);
    CHECK(view->datagram_count() == 1);
    CHECK(view->ecat_header().length == 0);
}

TEST_CASE("padding fills a short frame with zeros up to 60 bytes", "[wire]") {
    std::array<std::uint8_t, kMinFrameSize> buffer{};
    buffer.fill(0xee);
    CHECK(pad_to_minimum(buffer, 29) == kMinFrameSize);
    CHECK(buffer[28] == 0xee);
    for (std::size_t i = 29; i < kMinFrameSize; ++i) CHECK(buffer[i] == 0);
    CHECK(pad_to_minimum(buffer, 60) == 60);
}

TEST_CASE("command names, addressing and access kinds", "[wire]") {
    CHECK(to_string(Command::Nop) == "NOP");
    CHECK(to_string(Command::Frmw) == "FRMW");
    CHECK(to_string(static_cast<Command>(0x1f)) == "CMD(0x1f)");
    CHECK_FALSE(is_known(static_cast<Command>(15)));
    CHECK(addressing_of(Command::Armw) == Addressing::AutoIncrement);
    CHECK(addressing_of(Command::Frmw) == Addressing::Configured);
    CHECK(addressing_of(Command::Brw) == Addressing::Broadcast);
    CHECK(addressing_of(Command::Lrw) == Addressing::Logical);
    CHECK(addressing_of(Command::Nop) == Addressing::None);
    CHECK(addressing_of(static_cast<Command>(200)) == Addressing::Unknown);
    CHECK(command_reads(Command::Lrd));
    CHECK_FALSE(command_writes(Command::Lrd));
    CHECK(command_writes(Command::Lwr));
    CHECK_FALSE(command_reads(Command::Lwr));
    CHECK(command_reads(Command::Lrw));
    CHECK(command_writes(Command::Lrw));
    CHECK_FALSE(command_reads(Command::Nop));
    Command c{};
    REQUIRE(parse_command("lrw", c));
    CHECK(c == Command::Lrw);
    CHECK_FALSE(parse_command("LRX", c));
}

TEST_CASE("an unknown command code survives a decode/encode round trip", "[wire]") {
    auto bytes = kBrdAlStatus;
    bytes[16] = 0x2a;
    auto view = FrameView::parse(bytes);
    REQUIRE(view);
    const auto h = (*view->begin()).header();
    CHECK(static_cast<std::uint8_t>(h.command) == 0x2a);
    std::array<std::uint8_t, 10> out{};
    h.encode(out);
    CHECK(std::equal(out.begin(), out.end(), bytes.begin() + 16));
}

TEST_CASE("MAC addresses parse in the ENI and colon forms", "[wire]") {
    auto a = MacAddress::parse("010105010000");
    REQUIRE(a);
    CHECK(a->to_string() == "01:01:05:01:00:00");
    CHECK(a->is_group());
    auto b = MacAddress::parse("2c:58:b9:dc:a2:52");
    REQUIRE(b);
    CHECK_FALSE(b->is_group());
    CHECK_FALSE(MacAddress::parse("2c58b9dca2"));
    CHECK_FALSE(MacAddress::parse("zz58b9dca252"));
}
