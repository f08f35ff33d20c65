// Identification as an emulated slave offers it, and the ETG.1020 legacy
// race of an ID selector against the SII alias (hot-connect.md §9, §10):
// selector 0, selector with SII alias 0, both set (0x0012 = selector, SII
// alias cleared at INIT -> PREOP, SAFEOP refused with 0x0061 until INIT, a
// power cycle clears it for good); a slave that refuses states from one on;
// the input word.

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "esc_test_support.hpp"

namespace ecpair::sim::test {
namespace {

constexpr std::uint8_t kInit = 0x01;
constexpr std::uint8_t kPreop = 0x02;
constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kOp = 0x08;
constexpr std::uint8_t kError = 0x10;

struct LegacySlave {
    Line line;
    explicit LegacySlave(std::uint16_t sii_alias, std::uint16_t selector) : line({with(sii_alias, selector)}) {
        line.assign_station_addresses();
    }
    static EscDescription with(std::uint16_t sii_alias, std::uint16_t selector) {
        auto d = drive_description();
        d.alias = sii_alias;
        d.legacy_id_selector = selector;
        return d;
    }
    std::uint16_t alias_register() { return load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0012, 2), 0); }
    std::uint16_t sii_alias() { return load_le<std::uint16_t>(line[0].sii_image(), 8); }
    std::uint16_t code() { return load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0134, 2), 0); }
    std::uint8_t status() { return line.fprd(kFirstStation, 0x0130, 1)[0]; }
    void power_cycle() {
        line[0].power_off();
        line[0].power_on();
        line.assign_station_addresses();
    }
};

TEST_CASE("ETG.1020: selector 0 leaves the SII alias", "[esc][hotconnect]") {
    LegacySlave slave(0x0042, 0);
    CHECK(slave.alias_register() == 0x0042);
    CHECK(bring_drive_to(slave.line, kFirstStation, kOp) == kOp);
}

TEST_CASE("ETG.1020: a selector with SII alias 0 becomes the alias", "[esc][hotconnect]") {
    LegacySlave slave(0, 17);
    CHECK(slave.alias_register() == 17);
    CHECK(bring_drive_to(slave.line, kFirstStation, kOp) == kOp);
    CHECK(slave.sii_alias() == 0);
}

TEST_CASE("ETG.1020: both set -- the selector wins, SAFEOP is refused with 0x0061 until INIT", "[esc][hotconnect]") {
    LegacySlave slave(0x0042, 17);
    CHECK(slave.alias_register() == 17);
    CHECK(slave.sii_alias() == 0x0042);

    // An INIT request before the error was shown does not clear it (every master sends one first).
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0120, le16(0x0011)) == 1);
    CHECK(bring_drive_to(slave.line, kFirstStation, kPreop) == kPreop);
    CHECK(slave.sii_alias() == 0);  // overwritten at INIT -> PREOP

    REQUIRE(slave.line.fpwr(kFirstStation, 0x0120, le16(0x0004)) == 1);
    CHECK(slave.status() == (kPreop | kError));
    CHECK(slave.code() == 0x0061);
    // Acknowledging without INIT does not help.
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0120, le16(0x0014)) == 1);
    CHECK(slave.status() == (kPreop | kError));

    // INIT clears it; then the slave goes all the way with the selector as its alias.
    REQUIRE(slave.line.fpwr(kFirstStation, 0x0120, le16(0x0011)) == 1);
    CHECK(slave.status() == kInit);
    CHECK(bring_drive_to(slave.line, kFirstStation, kOp) == kOp);
    CHECK(slave.alias_register() == 17);

    SECTION("after a power cycle the SII alias is 0: no race any more") {
        slave.power_cycle();
        CHECK(slave.alias_register() == 17);
        CHECK(bring_drive_to(slave.line, kFirstStation, kOp) == kOp);
    }
}

TEST_CASE("a slave told to refuse SAFEOP stays in PREOP with an error", "[esc][hotconnect]") {
    Line line({drive_description()});
    line.assign_station_addresses();
    line[0].refuse_states_from(eni::SlaveState::Safeop);
    CHECK(bring_drive_to(line, kFirstStation, kOp) == (kPreop | kError));
    CHECK(load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0134, 2), 0) == 0x0001);
    line[0].refuse_states_from(std::nullopt);
    REQUIRE(line.fpwr(kFirstStation, 0x0120, le16(0x0011)) == 1);
    CHECK(bring_drive_to(line, kFirstStation, kOp) == kOp);
}

TEST_CASE("input-word identification: the value shows in the inputs from SAFEOP on", "[esc][hotconnect]") {
    auto d = drive_description();
    d.input_word_id = EscDescription::InputWord{0x1186, 0x0BEE};
    Line line({d});
    line.assign_station_addresses();
    CHECK(bring_drive_to(line, kFirstStation, kSafeop) == kSafeop);
    line.transact(physical(wire::Command::Brd, 0, 0x0130, {0, 0}));  // one more frame: the application runs
    CHECK(load_le<std::uint16_t>(line.fprd(kFirstStation, 0x1186, 2), 0) == 0x0BEE);
}

}  // namespace
}  // namespace ecpair::sim::test
