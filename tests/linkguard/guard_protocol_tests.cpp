// The link guard's messages: every kind round-trips, and malformed bytes are
// refused naming the offset and the problem.

#include <catch2/catch.hpp>

#include "ecpair/linkguard/guard_protocol.hpp"

using namespace ecpair::linkguard;

TEST_CASE("link guard messages round-trip", "[linkguard]") {
    for (const auto kind : {GuardMessageKind::Heartbeat, GuardMessageKind::LinksUp, GuardMessageKind::Shutdown,
                            GuardMessageKind::LinksAreUp, GuardMessageKind::LinksTakenDown,
                            GuardMessageKind::HeartbeatResumed}) {
        GuardMessage m;
        m.kind = kind;
        m.reason = DownReason::HeartbeatStopped;
        m.links = kMainLink | kRedLink;
        m.silence_ms = 0xA1B2C3D4u;
        m.error = -5;
        m.cycle = 0x0102030405060708ull;
        const auto bytes = encode(m);
        CHECK(bytes[0] == kGuardProtocolVersion);
        auto decoded = decode(bytes);
        REQUIRE(decoded);
        CHECK(*decoded == m);
    }
    CHECK(encode(GuardMessage{})[16] == 0);
    GuardMessage beat;
    beat.cycle = 0x0102;
    CHECK(encode(beat)[16] == 0x02);  // little endian
    CHECK(encode(beat)[17] == 0x01);
}

TEST_CASE("malformed link guard messages name the offset and the problem", "[linkguard]") {
    const auto good = encode(GuardMessage{});
    auto with = [&](std::size_t at, std::uint8_t value) {
        auto bytes = good;
        bytes[at] = value;
        return decode(bytes);
    };
    auto short_message = decode(ecpair::ConstBytes(good.data(), 10));
    REQUIRE_FALSE(short_message);
    CHECK(short_message.error().problem == "a link guard message has 24 bytes (got 10)");
    auto version = with(0, 9);
    REQUIRE_FALSE(version);
    CHECK(version.error().offset == 0);
    CHECK(version.error().problem == "protocol version 9 (this program speaks 1)");
    auto kind = with(1, 77);
    REQUIRE_FALSE(kind);
    CHECK(kind.error().offset == 1);
    CHECK(kind.error().problem == "unknown message kind 77");
    auto reason = with(2, 4);
    REQUIRE_FALSE(reason);
    CHECK(reason.error().offset == 2);
    auto links = with(3, 0x04);
    REQUIRE_FALSE(links);
    CHECK(links.error().problem == "unknown link bits 0x04");
    auto reserved = with(13, 1);
    REQUIRE_FALSE(reserved);
    CHECK(reserved.error().offset == 12);
}

TEST_CASE("link guard texts name the links and the reason", "[linkguard]") {
    CHECK(links_text(kMainLink | kRedLink) == "MAIN and RED");
    CHECK(links_text(kRedLink) == "RED");
    CHECK(links_text(0) == "no link");
    CHECK(describe(DownReason::DaemonGone).find("ecpaird is gone") != std::string_view::npos);
}
