// The bridge datagram (WIRE_FORMAT.md §11): what the writer seals decodes to
// the same header and frames; every way of breaking it is refused with its
// own code and the offset of the offending byte.

#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/common/crc32.hpp"
#include "ecpair/tap_bridge/bridge_datagram.hpp"

using namespace ecpair::tap_bridge;

namespace {

std::vector<std::uint8_t> ethernet_frame(std::size_t size, std::uint8_t fill) {
    std::vector<std::uint8_t> f(size, fill);
    f[12] = 0x08;  // EtherType IPv4
    f[13] = 0x00;
    return f;
}

// A sealed DATA datagram with two frames (60 and 100 bytes).
std::vector<std::uint8_t> sealed(std::size_t data_size = 200) {
    std::vector<std::uint8_t> data(data_size, 0xEE);
    BridgePayloadWriter writer(data);
    REQUIRE(writer.add(ethernet_frame(60, 0x11)));
    REQUIRE(writer.add(ethernet_frame(100, 0x22)));
    writer.seal(BridgeKind::Data, 0xA1B2C3D4, 77, 1234);
    return data;
}

BridgeErrc error_of(const std::vector<std::uint8_t>& data) {
    const auto d = decode_bridge_datagram(data, 100);
    REQUIRE_FALSE(d);
    return d.error().code;
}

}  // namespace

TEST_CASE("a sealed datagram decodes to its header and frames", "[tap_bridge]") {
    const auto data = sealed();
    const auto d = decode_bridge_datagram(data, 26);
    REQUIRE(d);
    CHECK(d->header.kind == BridgeKind::Data);
    CHECK(d->header.version == 1);
    CHECK(d->header.session == 0xA1B2C3D4);
    CHECK(d->header.sequence == 77);
    CHECK(d->header.backlog == 1234);
    CHECK(d->header.frame_count == 2);
    CHECK(d->header.length == 2 + 60 + 2 + 100);
    std::vector<std::vector<std::uint8_t>> frames;
    d->for_each_frame([&](ecpair::ConstBytes f) { frames.emplace_back(f.begin(), f.end()); });
    REQUIRE(frames.size() == 2);
    CHECK(frames[0] == ethernet_frame(60, 0x11));
    CHECK(frames[1] == ethernet_frame(100, 0x22));
    // The unused rest of the datagram is zeroed by seal().
    CHECK(data.back() == 0);
}

TEST_CASE("peek_kind reads the kind of a sealed datagram, and nothing from data too short to hold it", "[tap_bridge]") {
    auto data = sealed();
    CHECK(peek_kind(data) == BridgeKind::Data);
    BridgePayloadWriter writer(data);
    writer.seal(BridgeKind::Answer, 1, 2, 0);
    CHECK(peek_kind(data) == BridgeKind::Answer);
    CHECK(peek_kind(ecpair::ConstBytes(data).first(4)) == BridgeKind::Answer);
    CHECK_FALSE(peek_kind(ecpair::ConstBytes(data).first(3)));
    CHECK_FALSE(peek_kind(ecpair::ConstBytes{}));
}

TEST_CASE("the header bytes are where WIRE_FORMAT.md puts them", "[tap_bridge]") {
    const auto data = sealed();
    CHECK(data[0] == 'T');
    CHECK(data[1] == 'B');
    CHECK(data[2] == 1);
    CHECK(data[3] == 1);                        // DATA
    CHECK(data[4] == 164);                      // length, little-endian
    CHECK(data[5] == 0);
    CHECK(data[6] == 2);                        // frames
    CHECK(data[8] == 0xD4);                     // session
    CHECK(data[12] == 77);                      // sequence
    CHECK((data[16] | (data[17] << 8)) == 1234);  // backlog
    CHECK(data[24] == 60);                      // first frame's length
    CHECK(data[26] == 0x11);                    // and its first byte
}

TEST_CASE("sizes: 1462 payload bytes per datagram, MTU 1446", "[tap_bridge]") {
    CHECK(kMaxBridgePayload == 1462);
    CHECK(largest_frame(kMaxBridgeDatagramData) == 1460);
    CHECK(largest_mtu() == 1446);
    CHECK(largest_mtu(500) == 500 - 24 - 2 - 14);
    CHECK(largest_mtu(kMinPollData) == 0);
    std::vector<std::uint8_t> data(kMaxBridgeDatagramData);
    BridgePayloadWriter writer(data);
    CHECK_FALSE(writer.fits(1461));
    CHECK(writer.fits(1460));
    CHECK(writer.add(ethernet_frame(1460, 1)));
    CHECK_FALSE(writer.add(ethernet_frame(14, 1)));
    CHECK(writer.frame_count() == 1);
}

TEST_CASE("a poll is an empty datagram of its own size", "[tap_bridge]") {
    std::vector<std::uint8_t> data(300, 0xFF);
    BridgePayloadWriter writer(data);
    CHECK(writer.seal(BridgeKind::Poll, 5, 9, 0) == kBridgeHeaderSize);
    const auto d = decode_bridge_datagram(data);
    REQUIRE(d);
    CHECK(d->header.kind == BridgeKind::Poll);
    CHECK(d->payload.empty());
}

TEST_CASE("broken datagrams are refused, each with its reason and offset", "[tap_bridge]") {
    const auto good = sealed();
    SECTION("shorter than a header") {
        std::vector<std::uint8_t> d(good.begin(), good.begin() + 23);
        CHECK(error_of(d) == BridgeErrc::Truncated);
    }
    SECTION("shorter than its length") {
        std::vector<std::uint8_t> d(good.begin(), good.begin() + 100);
        const auto e = decode_bridge_datagram(d, 100);
        REQUIRE_FALSE(e);
        CHECK(e.error().code == BridgeErrc::Truncated);
        CHECK(e.error().offset == 104);  // the length field, from the frame's start
        CHECK(e.error().describe().find("Truncated at frame offset 104") != std::string::npos);
    }
    SECTION("magic") {
        auto d = good;
        d[1] = 'X';
        CHECK(error_of(d) == BridgeErrc::BadMagic);
    }
    SECTION("version") {
        auto d = good;
        d[2] = 2;
        CHECK(error_of(d) == BridgeErrc::UnsupportedVersion);
    }
    SECTION("kind") {
        auto d = good;
        d[3] = 7;
        CHECK(error_of(d) == BridgeErrc::UnknownKind);
    }
    SECTION("reserved bytes") {
        auto d = good;
        d[7] = 1;
        CHECK(error_of(d) == BridgeErrc::ReservedSet);
        d = good;
        d[19] = 1;
        CHECK(error_of(d) == BridgeErrc::ReservedSet);
    }
    SECTION("any bit of header or payload flipped") {
        for (const std::size_t at : {4u, 6u, 8u, 12u, 16u, 20u, 24u, 30u, 187u}) {
            auto d = good;
            d[at] ^= 0x10;
            const auto code = error_of(d);
            INFO("byte " << at);
            CHECK((code == BridgeErrc::BadChecksum || code == BridgeErrc::Truncated));
        }
    }
    SECTION("packed frames that do not add up, with a valid CRC") {
        // Rewrite the frames by hand and reseal so only the frame structure is wrong.
        auto reseal = [](std::vector<std::uint8_t> d, std::uint16_t length, std::uint8_t count) {
            d[4] = static_cast<std::uint8_t>(length);
            d[5] = static_cast<std::uint8_t>(length >> 8);
            d[6] = count;
            const auto crc = ecpair::crc32(ecpair::ConstBytes(d).subspan(24, length),
                                           ecpair::crc32(ecpair::ConstBytes(d).first(20)));
            for (std::size_t i = 0; i < 4; ++i) d[20 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
            return d;
        };
        CHECK(error_of(reseal(good, 164, 3)) == BridgeErrc::FrameCountMismatch);
        auto runt = good;
        runt[24] = 13;  // shorter than an Ethernet header
        CHECK(error_of(reseal(runt, 164, 2)) == BridgeErrc::BadFrameLength);
        auto past = good;
        past[24] = 200;  // runs past the payload
        CHECK(error_of(reseal(past, 164, 2)) == BridgeErrc::BadFrameLength);
        CHECK(error_of(reseal(good, 163, 2)) == BridgeErrc::BadFrameLength);  // a frame cut short
        auto poll = good;
        poll[3] = static_cast<std::uint8_t>(BridgeKind::Poll);
        CHECK(error_of(reseal(poll, 164, 2)) == BridgeErrc::PollNotEmpty);
    }
}
