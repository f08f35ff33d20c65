// The source-MAC semantic of design.md §2, with the four byte-0 values seen
// in a healthy ring (0x08, 0x88, 0x02, 0x06).

#include <catch2/catch.hpp>

#include "ecpair/wire/source_mac.hpp"

using ecpair::wire::MacAddress;
using ecpair::wire::NicBytes;
using ecpair::wire::SourceMac;

TEST_CASE("byte 0 bits encode retry index, redundancy and forwarding", "[wire][source_mac]") {
    SourceMac s;
    s.retry_index = 5;
    s.redundancy = true;
    s.frame_id = 0x42;
    s.nic = NicBytes{{0xaa, 0xbb, 0xcc}};
    const auto mac = s.encode();
    CHECK(mac.bytes == std::array<std::uint8_t, 6>{0x58, 0x42, 0x00, 0xaa, 0xbb, 0xcc});
    CHECK_FALSE(mac.is_group());
    CHECK(SourceMac::decode(mac) == s);
}

TEST_CASE("the four values of a healthy ring decode as design.md says", "[wire][source_mac]") {
    const auto at = [](std::uint8_t byte0) { return SourceMac::decode(MacAddress{{byte0, 7, 0, 1, 2, 3}}); };

    const auto inactive_main = at(0x08);  // sent on the ACTIVE's RED, straight over the master cable
    CHECK(inactive_main.redundancy);
    CHECK_FALSE(inactive_main.forwarded_red);
    CHECK_FALSE(inactive_main.slave_forwarded);

    const auto active_main = at(0x88);  // the same, forwarded out of the INACTIVE's RED
    CHECK(active_main.redundancy);
    CHECK(active_main.forwarded_red);
    CHECK_FALSE(active_main.forwarded_main);

    const auto inactive_red = at(0x02);  // sent on the ACTIVE's MAIN, processed by the slaves
    CHECK(inactive_red.slave_forwarded);
    CHECK_FALSE(inactive_red.redundancy);

    const auto active_red = at(0x06);  // the same, forwarded out of the INACTIVE's MAIN
    CHECK(active_red.slave_forwarded);
    CHECK(active_red.forwarded_main);
    CHECK_FALSE(active_red.forwarded_red);

    CHECK(active_red.frame_id == 7);
    CHECK(active_red.nic == NicBytes{{1, 2, 3}});
}

TEST_CASE("every byte-0 value round-trips", "[wire][source_mac]") {
    for (int b = 0; b < 256; ++b) {
        const MacAddress mac{{static_cast<std::uint8_t>(b), 0x11, 0x22, 0x33, 0x44, 0x55}};
        const auto decoded = SourceMac::decode(mac);
        CHECK(decoded.encode() == mac);
        CHECK(decoded.byte0() == b);
    }
}

TEST_CASE("the retry index keeps only 3 bits", "[wire][source_mac]") {
    SourceMac s;
    s.retry_index = 7;
    CHECK(s.byte0() == 0x70);
    s.retry_index = 9;  // out of range: wraps to 1 rather than touching other bits
    CHECK(s.byte0() == 0x10);
}
