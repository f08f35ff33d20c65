// Distributed clocks registers: system time, receive-time latch, the
// comparison a reference-time write feeds.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::uint64_t u64(const std::vector<std::uint8_t>& raw) { return load_le<std::uint64_t>(raw, 0); }
std::uint32_t u32(const std::vector<std::uint8_t>& raw) { return load_le<std::uint32_t>(raw, 0); }

}  // namespace

TEST_CASE("0x0910 reads as local time plus the offset, taken as the frame enters the processing unit") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    std::uint64_t t = line.time_ns();
    Frame frame({physical_read(Command::Fprd, 0x1001, 0x0910, 8), physical_read(Command::Fprd, 0x1002, 0x0910, 8)});
    line.run(frame);
    CHECK(u64(frame.datagram(0).data) == t + 100);  // the line adds 100 ns per hop
    CHECK(u64(frame.datagram(1).data) == t + 200);

    line.fpwr(0x1001, 0x0920, le32(1'000'000));
    t = line.time_ns();
    CHECK(u64(line.fprd(0x1001, 0x0910, 8)) == t + 100 + 1'000'000);
    // A write does not overwrite it.
    line.fpwr(0x1001, 0x0910, le32(0));
    t = line.time_ns();
    CHECK(u64(line.fprd(0x1001, 0x0910, 8)) == t + 100 + 1'000'000);
}

TEST_CASE("a write to 0x0900 latches the frame's receive time at every port") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    const std::uint64_t t = line.time_ns();
    Frame latch({physical(Command::Bwr, 0, 0x0900, le32(0))});
    line.run(latch);
    const std::uint64_t seq = line.last_frame_seq();
    CHECK(u32(line.fprd(0x1001, 0x0900, 4)) == static_cast<std::uint32_t>(t + 100));
    CHECK(u64(line.fprd(0x1001, 0x0918, 8)) == t + 100);
    CHECK(u32(line.fprd(0x1002, 0x0900, 4)) == static_cast<std::uint32_t>(t + 200));

    // The frame comes back through port 1 of the first slave later.
    line[0].frame_arrived_at_port(1, t + 500, seq);
    CHECK(u32(line.fprd(0x1001, 0x0904, 4)) == static_cast<std::uint32_t>(t + 500));
    // Another frame passing port 1 does not change the latch.
    line[0].frame_arrived_at_port(1, t + 900, seq + 100);
    CHECK(u32(line.fprd(0x1001, 0x0904, 4)) == static_cast<std::uint32_t>(t + 500));
}

TEST_CASE("ARMW on 0x0910 distributes the reference time - the others put the difference into 0x092C") {
    Line line({drive_description(), drive_description(), drive_description()});
    line.assign_station_addresses();
    line.fpwr(0x1002, 0x0928, le32(100));
    line.fpwr(0x1003, 0x0928, le32(300));
    const std::uint64_t t = line.time_ns();
    const Datagram armw = line.transact(physical(Command::Armw, 0, 0x0910, std::vector<std::uint8_t>(8, 0)));
    CHECK(armw.wkc == 3);
    CHECK(u64(armw.data) == t + 100);  // the reference clock's system time
    CHECK(u32(line.fprd(0x1002, 0x092C, 4)) == 0);  // (t+200) - (t+100 + 100)
    CHECK(u32(line.fprd(0x1003, 0x092C, 4)) == (0x80000000U | 100));  // local copy 100 ns behind
    CHECK(u32(line.fprd(0x1001, 0x092C, 4)) == 0);

    // FRMW with 4 bytes compares the low 32 bits.
    line.fpwr(0x1003, 0x0928, le32(0));
    line.transact(physical(Command::Frmw, 0x1001, 0x0910, le32(0)));
    CHECK(u32(line.fprd(0x1003, 0x092C, 4)) == 200);
}

TEST_CASE("cyclic unit registers are plain registers") {
    Line line({drive_description()});
    line.assign_station_addresses();
    line.fpwr(0x1001, 0x0990, le32(0x12345678));
    line.fpwr(0x1001, 0x09A0, le32(1'000'000));
    line.fpwr(0x1001, 0x0981, bytes({0x03}));
    CHECK(line.fprd(0x1001, 0x0990, 4) == le32(0x12345678));
    CHECK(line.fprd(0x1001, 0x09A0, 4) == le32(1'000'000));
    CHECK(line.fprd(0x1001, 0x0981, 1) == bytes({0x03}));
}
