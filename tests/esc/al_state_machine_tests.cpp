// The AL state machine seen through AL control/status (0x0120/0x0130/0x0134):
// allowed and refused transitions, the checks of a SOES-like stack, error
// acknowledge, explicit device identification, SyncManager changes.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

constexpr std::uint8_t kInit = 0x01;
constexpr std::uint8_t kPreop = 0x02;
constexpr std::uint8_t kBoot = 0x03;
constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kOp = 0x08;
constexpr std::uint8_t kError = 0x10;
constexpr std::uint8_t kIdLoaded = 0x20;
constexpr std::uint16_t kAck = 0x10;
constexpr std::uint16_t kIdRequest = 0x20;

const auto kMailboxSms =
    bytes({0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80, 0x00, 0x22, 0x00, 0x01, 0x00});
const auto kOutputSm = bytes({0x00, 0x11, 0x06, 0x00, 0x64, 0x00, 0x01, 0x00});
const auto kInputSm = bytes({0x80, 0x11, 0x08, 0x00, 0x20, 0x00, 0x01, 0x00});

struct Slave {
    Line line;
    std::uint16_t station = kFirstStation;

    explicit Slave(EscDescription description) : line({std::move(description)}) { line.assign_station_addresses(); }

    void request(std::uint16_t control) { REQUIRE(line.fpwr(station, 0x0120, le16(control)) == 1); }
    std::uint8_t status() { return line.fprd(station, 0x0130, 1)[0]; }
    std::uint16_t code() {
        const auto raw = line.fprd(station, 0x0134, 2);
        return static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
    }
    void write(std::uint16_t ado, const std::vector<std::uint8_t>& data) { REQUIRE(line.fpwr(station, ado, data) == 1); }
};

Slave drive_in(std::uint8_t state) {
    Slave slave(drive_description());
    REQUIRE(bring_drive_to(slave.line, slave.station, state) == state);
    return slave;
}

}  // namespace

TEST_CASE("INIT -> PREOP -> SAFEOP -> OP and back down, one state at a time") {
    Slave slave = drive_in(kOp);
    CHECK(slave.code() == 0);
    slave.request(kSafeop);
    CHECK(slave.status() == kSafeop);
    slave.request(kOp);
    CHECK(slave.status() == kOp);
    slave.request(kPreop);
    CHECK(slave.status() == kPreop);
    slave.request(kSafeop);
    CHECK(slave.status() == kSafeop);
    slave.request(kInit);
    CHECK(slave.status() == kInit);
    CHECK(slave.code() == 0);
}

TEST_CASE("PREOP needs the mailbox SyncManagers as the SII says (else 0x0016)") {
    Slave slave(drive_description());
    SECTION("not configured") {
        slave.request(kPreop);
        CHECK(slave.status() == (kInit | kError));
        CHECK(slave.code() == 0x0016);
    }
    SECTION("wrong length") {
        auto wrong = kMailboxSms;
        wrong[2] = 0x40;
        slave.write(0x0800, wrong);
        slave.request(kPreop);
        CHECK(slave.status() == (kInit | kError));
        CHECK(slave.code() == 0x0016);
    }
    SECTION("wrong control byte") {
        auto wrong = kMailboxSms;
        wrong[12] = 0x20;  // SM1 buffered instead of mailbox
        slave.write(0x0800, wrong);
        slave.request(kPreop);
        CHECK(slave.code() == 0x0016);
    }
    SECTION("not enabled") {
        auto wrong = kMailboxSms;
        wrong[6] = 0x00;
        slave.write(0x0800, wrong);
        slave.request(kPreop);
        CHECK(slave.code() == 0x0016);
    }
    SECTION("right") {
        slave.write(0x0800, kMailboxSms);
        slave.request(kPreop);
        CHECK(slave.status() == kPreop);
        CHECK(slave.code() == 0);
    }
}

TEST_CASE("a pending error ignores requests until acknowledged - INIT is always accepted") {
    Slave slave(drive_description());
    slave.request(kPreop);
    REQUIRE(slave.status() == (kInit | kError));
    slave.write(0x0800, kMailboxSms);

    slave.request(kPreop);  // no acknowledge: ignored
    CHECK(slave.status() == (kInit | kError));
    CHECK(slave.code() == 0x0016);

    SECTION("acknowledged with the request") {
        slave.request(kPreop | kAck);
        CHECK(slave.status() == kPreop);
        CHECK(slave.code() == 0);
    }
    SECTION("INIT without acknowledge") {
        slave.request(kInit);
        CHECK(slave.status() == kInit);
        CHECK(slave.code() == 0);
    }
    SECTION("acknowledge of the current state") {
        slave.request(kInit | kAck);
        CHECK(slave.status() == kInit);
        CHECK(slave.code() == 0);
    }
}

TEST_CASE("SAFEOP needs the process data SyncManagers of the configured size (0x001D / 0x001E)") {
    Slave slave = drive_in(kPreop);
    SECTION("outputs missing") {
        slave.write(0x0818, kInputSm);
        slave.request(kSafeop);
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x001D);
    }
    SECTION("inputs of the wrong size") {
        slave.write(0x0810, kOutputSm);
        auto wrong = kInputSm;
        wrong[2] = 0x0A;
        slave.write(0x0818, wrong);
        slave.request(kSafeop);
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x001E);
    }
    SECTION("both right") {
        slave.write(0x0810, kOutputSm);
        slave.write(0x0818, kInputSm);
        slave.request(kSafeop);
        CHECK(slave.status() == kSafeop);
    }
}

TEST_CASE("a slave without process data or mailbox accepts any SyncManager configuration") {
    Slave slave(coupler_description());
    slave.request(kPreop);
    CHECK(slave.status() == kPreop);
    slave.request(kSafeop);
    CHECK(slave.status() == kSafeop);
    slave.request(kOp);
    CHECK(slave.status() == kOp);
}

TEST_CASE("invalid transitions keep the state and report 0x0011") {
    SECTION("INIT -> SAFEOP / OP") {
        for (const std::uint8_t target : {kSafeop, kOp}) {
            Slave slave(drive_description());
            slave.request(target);
            CHECK(slave.status() == (kInit | kError));
            CHECK(slave.code() == 0x0011);
        }
    }
    SECTION("PREOP -> OP") {
        Slave slave = drive_in(kPreop);
        slave.request(kOp);
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x0011);
    }
    SECTION("PREOP -> BOOT") {
        Slave slave = drive_in(kPreop);
        slave.request(kBoot);
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x0011);
    }
    SECTION("OP -> BOOT falls back to SAFEOP") {
        Slave slave = drive_in(kOp);
        slave.request(kBoot);
        CHECK(slave.status() == (kSafeop | kError));
        CHECK(slave.code() == 0x0011);
    }
}

TEST_CASE("an undefined state value reports 0x0012") {
    Slave slave = drive_in(kPreop);
    slave.request(0x05);
    CHECK(slave.status() == (kPreop | kError));
    CHECK(slave.code() == 0x0012);

    Slave running = drive_in(kOp);
    running.request(0x0F);
    CHECK(running.status() == (kSafeop | kError));
    CHECK(running.code() == 0x0012);
}

TEST_CASE("BOOT: only from and to INIT, with the bootstrap mailbox - 0x0013 without one") {
    Slave slave(drive_description());
    slave.write(0x0800, kMailboxSms);  // the bootstrap mailbox has the same areas
    slave.request(kBoot);
    CHECK(slave.status() == kBoot);
    slave.request(kPreop);
    CHECK(slave.status() == (kBoot | kError));
    CHECK(slave.code() == 0x0011);
    slave.request(kInit);
    CHECK(slave.status() == kInit);

    Slave io(io_description());
    io.request(kBoot);
    CHECK(io.status() == (kInit | kError));
    CHECK(io.code() == 0x0013);
}

TEST_CASE("explicit device identification puts the ID into 0x0134 and sets status b5") {
    auto description = drive_description();
    description.id_selector = 0x0A0B;
    Slave slave(std::move(description));
    slave.write(0x0800, kMailboxSms);

    slave.request(kPreop | kIdRequest);
    CHECK(slave.status() == (kPreop | kIdLoaded));
    CHECK(slave.code() == 0x0A0B);

    slave.request(kPreop);  // without the request the ID goes away
    CHECK(slave.status() == kPreop);
    CHECK(slave.code() == 0);

    slave.line[0].set_id_selector(0x0C0D);  // the rotary switch turned
    slave.request(kInit | kIdRequest);
    CHECK(slave.status() == (kInit | kIdLoaded));
    CHECK(slave.code() == 0x0C0D);

    SECTION("no ID when the transition fails") {
        slave.write(0x0800, bytes({0, 0, 0, 0, 0, 0, 0, 0}));
        slave.request(kPreop | kIdRequest);
        CHECK(slave.status() == (kInit | kError));
        CHECK(slave.code() == 0x0016);
    }
    SECTION("no ID with a BOOT request") {
        slave.request(kBoot | kIdRequest);
        CHECK(slave.status() == kBoot);
        CHECK(slave.code() == 0);
    }
    SECTION("SAFEOP with ID only when SAFEOP is reached") {
        slave.request(kPreop);
        slave.write(0x0810, kOutputSm);
        slave.request(kSafeop | kIdRequest);  // SM3 missing
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x001E);
        slave.write(0x0818, kInputSm);
        slave.request(kSafeop | kAck | kIdRequest);
        CHECK(slave.status() == (kSafeop | kIdLoaded));
        CHECK(slave.code() == 0x0C0D);
    }
}

TEST_CASE("without an ID selector the device ID is the station alias - none at all loads nothing") {
    auto aliased = drive_description();
    aliased.alias = 0x0777;
    Slave slave(std::move(aliased));
    slave.request(kInit | kIdRequest);
    CHECK(slave.status() == (kInit | kIdLoaded));
    CHECK(slave.code() == 0x0777);

    Slave plain(drive_description());
    plain.request(kInit | kIdRequest);
    CHECK(plain.status() == kInit);
    CHECK(plain.code() == 0);
}

TEST_CASE("changing a SyncManager in PREOP/SAFEOP/OP is checked like SOES does") {
    SECTION("a broken mailbox drops the slave to INIT+ERR") {
        Slave slave = drive_in(kPreop);
        slave.write(0x0806, bytes({0x00}));  // SM0 disabled
        CHECK(slave.status() == (kInit | kError));
        CHECK(slave.code() == 0x0016);
    }
    SECTION("disabled outputs drop OP to PREOP+ERR") {
        Slave slave = drive_in(kOp);
        slave.write(0x0816, bytes({0x00}));
        CHECK(slave.status() == (kPreop | kError));
        CHECK(slave.code() == 0x001D);
    }
    SECTION("process data SyncManagers may change in PREOP") {
        Slave slave = drive_in(kPreop);
        slave.write(0x0816, bytes({0x00}));
        CHECK(slave.status() == kPreop);
    }
}

TEST_CASE("an AL status change raises the ECAT event - reading AL status clears it") {
    Slave slave(drive_description());
    slave.line.transact(physical_read(Command::Fprd, slave.station, 0x0130, 2));
    CHECK((slave.line.fprd(slave.station, 0x0210, 2)[0] & 0x08) == 0);
    slave.request(kPreop);  // fails: status becomes INIT+ERR
    CHECK((slave.line.fprd(slave.station, 0x0210, 2)[0] & 0x08) == 0x08);
    slave.line.transact(physical_read(Command::Brd, 0, 0x0130, 2));
    CHECK((slave.line.fprd(slave.station, 0x0210, 2)[0] & 0x08) == 0);
}
