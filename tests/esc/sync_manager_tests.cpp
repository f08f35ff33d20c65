// SyncManager semantics as the master sees them: mailbox alternation and
// its WKC, status flags, deactivation by the PDI, buffered mode as RAM.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

constexpr std::uint16_t kSm0 = 0x1000;  // master -> slave mailbox, 128 bytes
constexpr std::uint16_t kSm1 = 0x1080;  // slave -> master mailbox, 128 bytes

std::vector<std::uint8_t> coe_request(std::uint8_t counter) {
    std::vector<std::uint8_t> request(128, 0);
    request[0] = 10;  // length
    request[5] = static_cast<std::uint8_t>(0x03 | (counter << 4));  // CoE
    return request;
}

Line drive_in_preop() {
    Line line({drive_description()});
    line.assign_station_addresses();
    REQUIRE(bring_drive_to(line, kFirstStation, 0x02) == 0x02);
    return line;
}

}  // namespace

TEST_CASE("in INIT the slave stack keeps the mailbox SyncManagers deactivated") {
    Line line({drive_description()});
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0800,
              bytes({0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80, 0x00, 0x22, 0x00, 0x01, 0x00}));
    CHECK((line.fprd(kFirstStation, 0x0807, 1)[0] & 0x01) == 0x01);  // PDI control: deactivated
    CHECK(line.fpwr(kFirstStation, kSm0, coe_request(1)) == 0);
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, kSm1, 128)).wkc == 0);
}

TEST_CASE("the master mailbox takes one complete write, then refuses writes until the slave read it") {
    Line line = drive_in_preop();
    CHECK(line.fprd(kFirstStation, 0x0805, 1)[0] == 0x00);
    // Two writes in one frame: the second finds the mailbox full.
    Frame frame({physical(Command::Fpwr, kFirstStation, kSm0, coe_request(1)),
                 physical(Command::Fpwr, kFirstStation, kSm0, coe_request(2)),
                 physical_read(Command::Fprd, kFirstStation, 0x0805, 1)});
    line.run(frame);
    CHECK(frame.datagram(0).wkc == 1);
    CHECK(frame.datagram(1).wkc == 0);
    CHECK((frame.datagram(2).data[0] & 0x08) == 0x08);  // mailbox full, seen within the frame
    // After the frame the stack has read it: empty again, and its answer waits in SM1.
    CHECK((line.fprd(kFirstStation, 0x0805, 1)[0] & 0x08) == 0x00);
    CHECK((line.fprd(kFirstStation, 0x080D, 1)[0] & 0x08) == 0x08);
}

TEST_CASE("a mailbox access has to start at the first byte - the last byte completes it") {
    Line line = drive_in_preop();
    const auto request = coe_request(1);
    const std::vector<std::uint8_t> first(request.begin(), request.begin() + 64);
    const std::vector<std::uint8_t> second(request.begin() + 64, request.end());
    CHECK(line.fpwr(kFirstStation, kSm0 + 64, second) == 0);  // not from the start: refused
    CHECK(line.fpwr(kFirstStation, kSm0, first) == 1);
    CHECK((line.fprd(kFirstStation, 0x080D, 1)[0] & 0x08) == 0x00);  // not complete yet: no answer
    CHECK(line.fpwr(kFirstStation, kSm0 + 64, second) == 1);
    CHECK((line.fprd(kFirstStation, 0x080D, 1)[0] & 0x08) == 0x08);
}

TEST_CASE("the slave mailbox can be read only while full - reading it completely empties it") {
    Line line = drive_in_preop();
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, kSm1, 128)).wkc == 0);
    line.fpwr(kFirstStation, kSm0, coe_request(1));
    const Datagram reply = line.transact(physical_read(Command::Fprd, kFirstStation, kSm1, 128));
    CHECK(reply.wkc == 1);
    CHECK(reply.data[5] == (0x00 | (1 << 4)));  // a mailbox error reply, counter 1
    CHECK((line.fprd(kFirstStation, 0x080D, 1)[0] & 0x08) == 0x00);
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, kSm1, 128)).wkc == 0);
}

TEST_CASE("a refused mailbox byte does not count, accessible bytes in the same datagram do") {
    Line line = drive_in_preop();
    // 0x1078..0x1087: the last 8 bytes of the master mailbox (a read is the other direction and
    // passes unmanaged), then the first 8 bytes of the empty slave mailbox (refused).
    const Datagram mixed = line.transact(physical(Command::Fprd, kFirstStation, 0x1078, std::vector<std::uint8_t>(16, 0xEE)));
    CHECK(mixed.wkc == 1);
    CHECK(std::vector<std::uint8_t>(mixed.data.begin() + 8, mixed.data.end()) == std::vector<std::uint8_t>(8, 0xEE));
}

TEST_CASE("process data SyncManagers are deactivated by the PDI until SAFEOP") {
    Line line = drive_in_preop();
    line.fpwr(kFirstStation, 0x0810, bytes({0x00, 0x11, 0x06, 0x00, 0x64, 0x00, 0x01, 0x00}));
    line.fpwr(kFirstStation, 0x0818, bytes({0x80, 0x11, 0x08, 0x00, 0x20, 0x00, 0x01, 0x00}));
    CHECK(line.fpwr(kFirstStation, 0x1100, bytes({1, 2, 3, 4, 5, 6})) == 0);
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1180, 8)).wkc == 0);
    line.fpwr(kFirstStation, 0x0120, le16(0x0004));
    REQUIRE(line[0].al_status() == 0x04);
    CHECK((line.fprd(kFirstStation, 0x0817, 1)[0] & 0x01) == 0x00);
    // Buffered mode is plain memory for the master.
    CHECK(line.fpwr(kFirstStation, 0x1100, bytes({1, 2, 3, 4, 5, 6})) == 1);
    CHECK(line.fprd(kFirstStation, 0x1100, 6) == bytes({1, 2, 3, 4, 5, 6}));
    CHECK(line.fpwr(kFirstStation, 0x1100, bytes({9, 9, 9, 9, 9, 9})) == 1);
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1180, 8)).wkc == 1);
    // Written completely: the status shows the write event and a last buffer.
    CHECK((line.fprd(kFirstStation, 0x0815, 1)[0] & 0x01) == 0x01);
}

TEST_CASE("a SyncManager the master disabled, or of length 1, does not interfere") {
    Line line({io_description()});
    line.assign_station_addresses();
    // Mailbox mode, ECAT reads, but disabled: plain memory.
    line.fpwr(kFirstStation, 0x0820, bytes({0x00, 0x14, 0x10, 0x00, 0x02, 0x00, 0x00, 0x00}));
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1400, 16)).wkc == 1);
    // Enabled, 1 byte long: no buffer handling.
    line.fpwr(kFirstStation, 0x0820, bytes({0x00, 0x14, 0x01, 0x00, 0x02, 0x00, 0x01, 0x00}));
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1400, 1)).wkc == 1);
    // Enabled, 16 bytes, empty: reads refused.
    line.fpwr(kFirstStation, 0x0820, bytes({0x00, 0x14, 0x10, 0x00, 0x02, 0x00, 0x01, 0x00}));
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1400, 16)).wkc == 0);
}

TEST_CASE("a logical read of a blocked mailbox does not count") {
    Line line = drive_in_preop();
    // FMMU 2 maps the slave mailbox (empty) to logical 0x09000000.
    line.fpwr(kFirstStation, 0x0620, bytes({0x00, 0x00, 0x00, 0x09, 0x80, 0x00, 0x00, 0x07, 0x80, 0x10, 0x00, 0x01, 0x01, 0, 0, 0}));
    CHECK(line.transact(logical(Command::Lrd, 0x09000000, std::vector<std::uint8_t>(128, 0))).wkc == 0);
    line.fpwr(kFirstStation, kSm0, coe_request(1));
    CHECK(line.transact(logical(Command::Lrd, 0x09000000, std::vector<std::uint8_t>(128, 0))).wkc == 1);
}

TEST_CASE("the mailbox-full bit of SM1 can be mapped to a logical bit (mailbox state FMMU)") {
    Line line = drive_in_preop();
    // As the ENIs do: logical 0x09000000 bit 0 <- 0x080D bit 3.
    line.fpwr(kFirstStation, 0x0620, bytes({0x00, 0x00, 0x00, 0x09, 0x01, 0x00, 0x00, 0x00, 0x0D, 0x08, 0x03, 0x01, 0x01, 0, 0, 0}));
    CHECK(line.transact(logical(Command::Lrd, 0x09000000, bytes({0}))).data == bytes({0}));
    line.fpwr(kFirstStation, kSm0, coe_request(1));
    const Datagram state = line.transact(logical(Command::Lrd, 0x09000000, bytes({0})));
    CHECK(state.wkc == 1);
    CHECK(state.data == bytes({1}));
}
