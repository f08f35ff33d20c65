// Logical addressing through the FMMUs: byte and bit mappings, masking of
// LRD/LRW reads, WKC per slave, partial overlaps, lower FMMU wins.

#include <catch2/catch.hpp>

#include "ecpair/wire/fmmu_config.hpp"
#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::vector<std::uint8_t> fmmu(std::uint32_t logical, std::uint16_t length, std::uint8_t start_bit, std::uint8_t stop_bit,
                               std::uint16_t physical, std::uint8_t physical_bit, bool read, bool write) {
    wire::FmmuConfig config;
    config.logical_start = logical;
    config.length = length;
    config.logical_start_bit = start_bit;
    config.logical_stop_bit = stop_bit;
    config.physical_start = physical;
    config.physical_start_bit = physical_bit;
    config.read = read;
    config.write = write;
    config.active = true;
    std::vector<std::uint8_t> encoded(wire::FmmuConfig::kSize);
    config.encode(encoded);
    return encoded;
}

std::vector<std::uint8_t> bytes_fmmu(std::uint32_t logical, std::uint16_t length, std::uint16_t physical, bool read,
                                     bool write) {
    return fmmu(logical, length, 0, 7, physical, 0, read, write);
}

// Two slaves; each writes 2 bytes to 0x1400 and reads 2 bytes from 0x1500:
// slave 1 at logical 0x10000/0x10002, slave 2 at 0x10004/0x10006.
Line two_mapped_slaves() {
    Line line({io_description("a"), io_description("b")});
    line.assign_station_addresses();
    for (std::uint16_t i = 0; i < 2; ++i) {
        const auto station = static_cast<std::uint16_t>(kFirstStation + i);
        const std::uint32_t base = 0x10000U + 4U * i;
        REQUIRE(line.fpwr(station, 0x0600, bytes_fmmu(base, 2, 0x1400, false, true)) == 1);
        REQUIRE(line.fpwr(station, 0x0610, bytes_fmmu(base + 2, 2, 0x1500, true, false)) == 1);
        line[i].write_memory(0x1500, bytes({0xA0 + 2 * i, 0xA1 + 2 * i}));
    }
    return line;
}

}  // namespace

TEST_CASE("LRW through byte-aligned FMMUs: writes outputs, reads inputs, +3 per slave") {
    Line line = two_mapped_slaves();
    const Datagram lrw = line.transact(logical(Command::Lrw, 0x10000, bytes({1, 2, 3, 4, 5, 6, 7, 8})));
    CHECK(lrw.wkc == 6);
    CHECK(lrw.data == bytes({1, 2, 0xA0, 0xA1, 5, 6, 0xA2, 0xA3}));
    CHECK(lrw.address == 0x10000);  // the logical address is not changed
    CHECK(line[0].read_memory(0x1400, 2) == bytes({1, 2}));
    CHECK(line[1].read_memory(0x1400, 2) == bytes({5, 6}));
}

TEST_CASE("LRD and LWR count 1 per slave and only touch their own direction") {
    Line line = two_mapped_slaves();
    const Datagram lrd = line.transact(logical(Command::Lrd, 0x10000, bytes({9, 9, 9, 9, 9, 9, 9, 9})));
    CHECK(lrd.wkc == 2);
    CHECK(lrd.data == bytes({9, 9, 0xA0, 0xA1, 9, 9, 0xA2, 0xA3}));
    CHECK(line[0].read_memory(0x1400, 2) == bytes({0, 0}));

    const Datagram lwr = line.transact(logical(Command::Lwr, 0x10000, bytes({1, 2, 3, 4, 5, 6, 7, 8})));
    CHECK(lwr.wkc == 2);
    CHECK(lwr.data == bytes({1, 2, 3, 4, 5, 6, 7, 8}));
    CHECK(line[0].read_memory(0x1400, 2) == bytes({1, 2}));
    CHECK(line[1].read_memory(0x1400, 2) == bytes({5, 6}));
    CHECK(line[0].read_memory(0x1500, 2) == bytes({0xA0, 0xA1}));
}

TEST_CASE("a datagram that overlaps an FMMU only partly moves the overlapping bytes") {
    Line line = two_mapped_slaves();
    // Logical 0x10003..0x10004: the second read byte of slave 1, the first write byte of slave 2.
    const Datagram lrw = line.transact(logical(Command::Lrw, 0x10003, bytes({0x55, 0x66})));
    CHECK(lrw.wkc == 1 + 2);
    CHECK(lrw.data == bytes({0xA1, 0x66}));
    CHECK(line[1].read_memory(0x1400, 2) == bytes({0x66, 0x00}));
    // A datagram ending inside a mapping: logical 0x0FFFF..0x10000.
    const Datagram lwr = line.transact(logical(Command::Lwr, 0xFFFF, bytes({0x77, 0x88})));
    CHECK(lwr.wkc == 1);
    CHECK(line[0].read_memory(0x1400, 2) == bytes({0x88, 0x00}));
    // No mapping at all: nothing counts, nothing changes.
    const Datagram miss = line.transact(logical(Command::Lrw, 0x20000, bytes({1, 2})));
    CHECK(miss.wkc == 0);
    CHECK(miss.data == bytes({1, 2}));
}

TEST_CASE("bit-granular mapping as in the datasheet example: 14 bits from logical 0x10011.3 to 0x0F01.1") {
    Line line({io_description()});
    line.assign_station_addresses();
    REQUIRE(line.fpwr(kFirstStation, 0x0600, fmmu(0x00010011, 3, 3, 0, 0x0F01, 1, true, true)) == 1);

    const Datagram lwr = line.transact(logical(Command::Lwr, 0x10010, bytes({0xFF, 0xFF, 0xFF, 0xFF})));
    CHECK(lwr.wkc == 1);
    CHECK(line[0].read_memory(0x0F00, 4) == bytes({0x00, 0xFE, 0x7F, 0x00}));

    // LRD: mapped bits come from memory, the others stay as they arrived.
    const Datagram lrd = line.transact(logical(Command::Lrd, 0x10010, bytes({0xAA, 0xAA, 0xAA, 0xAA})));
    CHECK(lrd.wkc == 1);
    CHECK(lrd.data == bytes({0xAA, 0xFA, 0xFF, 0xAB}));

    // LRW: the read returns memory before the write, the write stores what arrived.
    line[0].write_memory(0x0F01, bytes({0x00, 0x00}));
    const Datagram lrw = line.transact(logical(Command::Lrw, 0x10011, bytes({0b0101'1000, 0x0F, 0x01})));
    CHECK(lrw.wkc == 3);
    CHECK(lrw.data == bytes({0x00, 0x00, 0x00}));
    // logical 0x10011 bits 3..7 = 1,1,0,1,0 -> physical 0x0F01 bits 1..5;
    // 0x10012 bits 0..7 = 0x0F -> 0x0F01 bits 6,7 and 0x0F02 bits 0..5;
    // 0x10013 bit 0 = 1 -> 0x0F02 bit 6.
    CHECK(line[0].read_memory(0x0F01, 2) == bytes({0b1101'0110, 0b0100'0011}));
}

TEST_CASE("bits of several slaves share one logical byte") {
    Line line({io_description("low"), io_description("high")});
    line.assign_station_addresses();
    REQUIRE(line.fpwr(kFirstStation, 0x0600, fmmu(0x20000, 1, 0, 3, 0x1600, 0, true, false)) == 1);
    REQUIRE(line.fpwr(kFirstStation + 1, 0x0600, fmmu(0x20000, 1, 4, 7, 0x1600, 0, true, false)) == 1);
    line[0].write_memory(0x1600, bytes({0x05}));
    line[1].write_memory(0x1600, bytes({0x0A}));
    const Datagram lrd = line.transact(logical(Command::Lrd, 0x20000, bytes({0x00})));
    CHECK(lrd.wkc == 2);
    CHECK(lrd.data == bytes({0xA5}));
}

TEST_CASE("when two FMMUs map the same logical byte the lower one wins") {
    Line line({io_description()});
    line.assign_station_addresses();
    REQUIRE(line.fpwr(kFirstStation, 0x0600, bytes_fmmu(0x30000, 1, 0x1600, true, false)) == 1);
    REQUIRE(line.fpwr(kFirstStation, 0x0610, bytes_fmmu(0x30000, 2, 0x1700, true, false)) == 1);
    line[0].write_memory(0x1600, bytes({0x11}));
    line[0].write_memory(0x1700, bytes({0x22, 0x33}));
    const Datagram lrd = line.transact(logical(Command::Lrd, 0x30000, bytes({0, 0})));
    CHECK(lrd.wkc == 1);
    CHECK(lrd.data == bytes({0x11, 0x33}));
}

TEST_CASE("a read/write FMMU returns the old memory and stores the arriving data") {
    Line line({io_description()});
    line.assign_station_addresses();
    REQUIRE(line.fpwr(kFirstStation, 0x0600, bytes_fmmu(0x40000, 2, 0x1600, true, true)) == 1);
    line[0].write_memory(0x1600, bytes({0x01, 0x02}));
    const Datagram lrw = line.transact(logical(Command::Lrw, 0x40000, bytes({0x0A, 0x0B})));
    CHECK(lrw.wkc == 3);
    CHECK(lrw.data == bytes({0x01, 0x02}));
    CHECK(line[0].read_memory(0x1600, 2) == bytes({0x0A, 0x0B}));
}

TEST_CASE("an inactive FMMU or one of the wrong type maps nothing") {
    Line line({io_description()});
    line.assign_station_addresses();
    auto inactive = bytes_fmmu(0x50000, 2, 0x1600, true, true);
    inactive[12] = 0;
    REQUIRE(line.fpwr(kFirstStation, 0x0600, inactive) == 1);
    REQUIRE(line.fpwr(kFirstStation, 0x0610, bytes_fmmu(0x60000, 2, 0x1600, false, true)) == 1);
    CHECK(line.transact(logical(Command::Lrd, 0x50000, bytes({0, 0}))).wkc == 0);
    CHECK(line.transact(logical(Command::Lrd, 0x60000, bytes({0, 0}))).wkc == 0);
    CHECK(line.transact(logical(Command::Lwr, 0x60000, bytes({1, 1}))).wkc == 1);
}
