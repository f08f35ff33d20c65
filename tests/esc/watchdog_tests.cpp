// The process data watchdog (issue 11, item 7): writes to a SyncManager with
// the watchdog trigger restart it; (0x0400 + 2) x 40 ns x 0x0420 after the
// last one (100 ms after reset) it expires: 0x0440 b0 = 0, 0x0442 counts,
// the outputs are cleared and a stack in OP falls to SAFEOP+ERR 0x001B.
// Device emulation keeps its AL state. The ENI's InitCmds may rewrite the
// divider and the time, or switch the watchdog off (0x0420 = 0).

#include <functional>

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;

namespace {

constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kOp = 0x08;
constexpr std::uint8_t kError = 0x10;
constexpr std::uint16_t kOutputs = 0x1100;  // drive_description(): SM2, 6 bytes, control 0x64
constexpr std::uint64_t kMs = 1'000'000;

struct Drive {
    Line line{{drive_description()}};
    // `configure` runs before OP, like the ENIs' IP InitCmds ("set watchdog divider", "set SM watchdog").
    explicit Drive(const std::function<void(Line&)>& configure = {}) {
        line.assign_station_addresses();
        if (configure) configure(line);
    }
    void bring_to_op() { REQUIRE(bring_drive_to(line, kFirstStation, kOp) == kOp); }
    void write_outputs(std::uint8_t value) {
        REQUIRE(line.fpwr(kFirstStation, kOutputs, std::vector<std::uint8_t>(6, value)) == 1);
    }
    std::uint8_t status() { return line.fprd(kFirstStation, 0x0130, 1)[0]; }
    std::uint16_t code() { return load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0134, 2), 0); }
    std::uint16_t watchdog_status() { return load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0440, 2), 0); }
    std::uint8_t watchdog_counter() { return line.fprd(kFirstStation, 0x0442, 1)[0]; }
    std::vector<std::uint8_t> outputs() { return line[0].read_memory(kOutputs, 6); }
};

}  // namespace

TEST_CASE("100 ms after the last output write a drive in OP falls to SAFEOP+ERR 0x001B with its outputs cleared") {
    Drive drive;
    drive.bring_to_op();
    CHECK(drive.watchdog_status() == 0);  // enabled, not triggered yet: reads expired
    drive.write_outputs(0x5A);
    CHECK(drive.watchdog_status() == 1);
    drive.line.advance(99 * kMs);
    CHECK(drive.status() == kOp);
    CHECK(drive.outputs() == std::vector<std::uint8_t>(6, 0x5A));
    drive.line.advance(2 * kMs);
    CHECK(drive.status() == (kSafeop | kError));
    CHECK(drive.code() == 0x001B);
    CHECK(drive.watchdog_status() == 0);
    CHECK(drive.watchdog_counter() == 1);
    CHECK(drive.outputs() == std::vector<std::uint8_t>(6, 0));
    // The master acknowledges and brings it back.
    REQUIRE(drive.line.fpwr(kFirstStation, 0x0120, le16(0x0014)) == 1);
    CHECK(drive.status() == kSafeop);
    drive.write_outputs(0x11);
    REQUIRE(drive.line.fpwr(kFirstStation, 0x0120, le16(0x0008)) == 1);
    CHECK(drive.status() == kOp);
    CHECK(drive.code() == 0);
    // A write to the counter clears it.
    REQUIRE(drive.line.fpwr(kFirstStation, 0x0442, {0}) == 1);
    CHECK(drive.watchdog_counter() == 0);
}

TEST_CASE("outputs written every cycle keep the watchdog running and the drive in OP") {
    Drive drive;
    drive.bring_to_op();
    for (int cycle = 0; cycle < 40; ++cycle) {
        drive.write_outputs(static_cast<std::uint8_t>(cycle));
        drive.line.advance(50 * kMs);
    }
    CHECK(drive.status() == kOp);
    CHECK(drive.watchdog_status() == 1);
    CHECK(drive.watchdog_counter() == 0);
}

TEST_CASE("the watchdog time follows 0x0400 and 0x0420 as the master wrote them") {
    Drive drive([](Line& line) {
        REQUIRE(line.fpwr(kFirstStation, 0x0400, le16(498)) == 1);   // (498 + 2) x 40 ns = 20 us
        REQUIRE(line.fpwr(kFirstStation, 0x0420, le16(1000)) == 1);  // 20 ms
    });
    drive.bring_to_op();
    drive.write_outputs(1);
    drive.line.advance(19 * kMs);
    CHECK(drive.status() == kOp);
    drive.line.advance(2 * kMs);
    CHECK(drive.status() == (kSafeop | kError));
    CHECK(drive.code() == 0x001B);
}

TEST_CASE("0x0420 = 0 switches the watchdog off (as elmo_eas_rocos_1slave.xml's InitCmds do)") {
    Drive drive([](Line& line) { REQUIRE(line.fpwr(kFirstStation, 0x0420, le16(0)) == 1); });
    drive.bring_to_op();
    CHECK(drive.watchdog_status() == 1);  // disabled reads as running
    drive.write_outputs(7);
    drive.line.advance(10'000 * kMs);
    CHECK(drive.status() == kOp);
    CHECK(drive.watchdog_counter() == 0);
    CHECK(drive.outputs() == std::vector<std::uint8_t>(6, 7));
}

TEST_CASE("a drive that never received outputs in OP is not failed by the watchdog (TwinCAT compatibility)") {
    Drive drive;
    drive.bring_to_op();
    drive.line.advance(1'000 * kMs);
    CHECK(drive.status() == kOp);
}

TEST_CASE("without any frame the watchdog expires when the ESC is told the time") {
    Drive drive;
    drive.bring_to_op();
    CHECK_FALSE(drive.line[0].next_deadline());
    drive.write_outputs(3);
    const auto deadline = drive.line[0].next_deadline();
    REQUIRE(deadline);
    CHECK(*deadline >= drive.line.time_ns() + 99 * kMs);
    CHECK(*deadline <= drive.line.time_ns() + 100 * kMs);
    drive.line[0].advance_time(*deadline - 1);
    CHECK(drive.line[0].al_status() == kOp);
    drive.line[0].advance_time(*deadline);
    CHECK(drive.line[0].al_status() == (kSafeop | kError));
    CHECK(drive.line[0].al_status_code() == 0x001B);
    CHECK_FALSE(drive.line[0].next_deadline());
}

TEST_CASE("in device emulation an expired watchdog clears the digital outputs and the AL state stays") {
    Line line({digital_output_description()});
    line.assign_station_addresses();
    REQUIRE(line.fpwr(kFirstStation, 0x0120, le16(kOp)) == 1);
    REQUIRE(line.fpwr(kFirstStation, 0x0800, bytes({0x00, 0x0F, 0x01, 0x00, 0x44, 0x00, 0x01, 0x00})) == 1);
    REQUIRE(line.fpwr(kFirstStation, 0x0F00, {0xA5}) == 1);
    line.advance(50 * kMs);
    CHECK(line.fprd(kFirstStation, 0x0F00, 1)[0] == 0xA5);
    line.advance(51 * kMs);
    CHECK(line.fprd(kFirstStation, 0x0F00, 1)[0] == 0x00);
    CHECK(line.fprd(kFirstStation, 0x0130, 1)[0] == kOp);
    CHECK(line.fprd(kFirstStation, 0x0442, 1)[0] == 1);
}

TEST_CASE("writes to a SyncManager without the watchdog trigger do not feed it") {
    Drive drive;
    drive.bring_to_op();
    drive.write_outputs(1);
    drive.line.advance(60 * kMs);
    // SM3 (inputs, control 0x20) is read by the master; a write there feeds nothing.
    drive.line.fpwr(kFirstStation, 0x1180, std::vector<std::uint8_t>(8, 0));
    drive.line.advance(60 * kMs);
    CHECK(drive.status() == (kSafeop | kError));
}
