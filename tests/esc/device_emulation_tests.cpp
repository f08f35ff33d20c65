// Slaves without a microcontroller (issue 11, finding 2): an ESC whose SII
// sets device emulation (0x0141 b0) copies AL control into AL status with
// no SyncManager check, as the digital I/O terminals and couplers do; every
// slave with a stack keeps its checks.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;

namespace {

constexpr std::uint8_t kInit = 0x01;
constexpr std::uint8_t kPreop = 0x02;
constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kOp = 0x08;
constexpr std::uint8_t kError = 0x10;

struct OneSlave {
    Line line;
    explicit OneSlave(EscDescription description) : line({std::move(description)}) { line.assign_station_addresses(); }
    void request(std::uint16_t control) { REQUIRE(line.fpwr(kFirstStation, 0x0120, le16(control)) == 1); }
    std::uint8_t status() { return line.fprd(kFirstStation, 0x0130, 1)[0]; }
    std::uint16_t code() {
        const auto raw = line.fprd(kFirstStation, 0x0134, 2);
        return static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
    }
    std::uint8_t esc_config() { return line.fprd(kFirstStation, 0x0141, 1)[0]; }
};

}  // namespace

TEST_CASE("a digital output terminal runs in device emulation: its SII says so and 0x0141 b0 is set") {
    OneSlave slave(digital_output_description());
    const auto& sii = slave.line[0].sii_image();
    CHECK((sii[0] | (sii[1] << 8)) == 0x0104);  // digital I/O PDI, device emulation
    CHECK((slave.esc_config() & 0x01) == 0x01);
}

TEST_CASE("in device emulation AL status follows AL control without SyncManager checks") {
    OneSlave slave(digital_output_description());
    // No SyncManager is configured at all: a stack would refuse SAFEOP with 0x001D.
    slave.request(kPreop);
    CHECK(slave.status() == kPreop);
    slave.request(kSafeop);
    CHECK(slave.status() == kSafeop);
    slave.request(kOp);
    CHECK(slave.status() == kOp);
    CHECK(slave.code() == 0);
    // The output SM is enabled in OP only (as the configurator does) and cleared again.
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0800, bytes({0x00, 0x0F, 0x01, 0x00, 0x44, 0x00, 0x01, 0x00})) == 1);
    CHECK(slave.status() == kOp);
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0800, std::vector<std::uint8_t>(8, 0)) == 1);
    CHECK(slave.status() == kOp);
    // Even a jump a stack refuses (OP -> INIT -> OP) is copied: no error, no code.
    slave.request(kInit);
    slave.request(kOp);
    CHECK(slave.status() == kOp);
    CHECK(slave.code() == 0);
}

TEST_CASE("in device emulation the outputs written through the SM reach the digital output register in any state") {
    OneSlave slave(digital_output_description());
    slave.request(kSafeop);
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0800, bytes({0x00, 0x0F, 0x01, 0x00, 0x44, 0x00, 0x01, 0x00})) == 1);
    CHECK(slave.line.fpwr(kFirstStation, 0x0F00, {0xA5}) == 1);
    CHECK(slave.line.fprd(kFirstStation, 0x0F00, 1)[0] == 0xA5);
    // No stack deactivates the SM from the PDI side.
    CHECK((slave.line.fprd(kFirstStation, 0x0807, 1)[0] & 0x01) == 0);
}

TEST_CASE("a coupler (no mailbox, no process data SM) keeps the stack model: no check applies, it answers ID requests") {
    OneSlave slave(coupler_description());
    CHECK((slave.esc_config() & 0x01) == 0);
    slave.request(kPreop);
    CHECK(slave.status() == kPreop);
    slave.request(kSafeop);
    CHECK(slave.status() == kSafeop);
    slave.request(kOp);
    CHECK(slave.status() == kOp);
    slave.line[0].set_id_selector(0x0042);
    slave.request(0x0020 | kOp);  // explicit device ID request
    CHECK(slave.code() == 0x0042);
}

TEST_CASE("slaves with a stack keep their checks: process data in RAM without mailbox, and mailbox slaves") {
    SECTION("outputs in process RAM (0x1000), no mailbox: SAFEOP needs the output SM") {
        OneSlave slave(io_description());
        const auto& sii = slave.line[0].sii_image();
        CHECK((sii[0] | (sii[1] << 8)) == 0x0C05);
        CHECK((slave.esc_config() & 0x01) == 0);
        slave.request(kPreop);
        REQUIRE(slave.status() == kPreop);
        slave.request(kSafeop);
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x001D);
    }
    SECTION("a drive with a mailbox: PREOP needs the mailbox SMs") {
        OneSlave slave(drive_description());
        CHECK((slave.esc_config() & 0x01) == 0);
        slave.request(kPreop);
        CHECK(slave.status() == (kInit | kError));
        CHECK(slave.code() == 0x0016);
    }
}
