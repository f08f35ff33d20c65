// InitCmdRunner against a scripted bus: Validate, Retries, Cnt, the DC
// start time, addressing, and the words of its errors.

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "fakes.hpp"

namespace ecpair::test {
namespace {

using sequencer::CommandContext;
using sequencer::InitCmdFailure;
using sequencer::InitCmdRunner;

eni::EcatCmd check_safeop() {
    eni::EcatCmd cmd;
    cmd.comment = "check device state for SAFEOP";
    cmd.command = wire::Command::Fprd;
    cmd.adp = 1001;
    cmd.ado = wire::reg::kAlStatus;
    cmd.data.assign(6, 0);
    cmd.expected_wkc = 1;
    cmd.retries = 3;
    cmd.source_line = 42;
    cmd.validate = eni::Validate{{0x04, 0, 0, 0, 0, 0}, {0x1f, 0, 0, 0, 0, 0}, std::chrono::milliseconds(200)};
    return cmd;
}

CommandContext drive() {
    CommandContext context;
    context.owner = "Drive";
    context.station = 1001;
    context.slave_index = 0;
    return context;
}

eni::EcatCmd write_al_control(std::uint32_t retries) {
    eni::EcatCmd cmd;
    cmd.comment = "set device state to PREOP";
    cmd.command = wire::Command::Fpwr;
    cmd.adp = 1001;
    cmd.ado = wire::reg::kAlControl;
    cmd.data = {0x02, 0x00};
    cmd.expected_wkc = 1;
    cmd.retries = retries;
    cmd.source_line = 7;
    return cmd;
}

TEST_CASE("Validate passes once the slave shows the state", "[sequencer][initcmd]") {
    int reads = 0;
    ScriptedBus bus([&reads](const bus::DatagramRequest&) {
        ++reads;
        return reply({static_cast<std::uint8_t>(reads < 4 ? 0x02 : 0x04), 0, 0, 0, 0, 0}, 1);
    });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    REQUIRE(runner.run(check_safeop(), drive()));
    CHECK(reads == 4);  // the command, then three more reads until SAFEOP shows
    for (const auto& r : bus.requests()) {
        CHECK(r.command == wire::Command::Fprd);
        CHECK(adp_of(r) == 1001);
        CHECK(ado_of(r) == wire::reg::kAlStatus);
    }
}

TEST_CASE("Validate that never matches fails with expected, mask, last read and AL status", "[sequencer][initcmd]") {
    // PREOP with the error flag and code 0x001d (invalid output configuration).
    ScriptedBus bus([](const bus::DatagramRequest&) { return reply({0x12, 0, 0, 0, 0x1d, 0}, 1); });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    const auto result = runner.run(check_safeop(), drive());
    REQUIRE_FALSE(result);
    const auto& error = result.error();
    CHECK(error.failure == InitCmdFailure::ValidateFailed);
    CHECK(error.eni_line == 42);
    REQUIRE(error.al_status);
    CHECK(error.al_status->raw == 0x12);
    CHECK(error.al_status_code == std::uint16_t{0x001d});
    const auto text = error.describe();
    CHECK_THAT(text, Catch::Contains("slave 'Drive' (station 1001), ENI line 42 'check device state for SAFEOP'"));
    CHECK_THAT(text, Catch::Contains("validate: expected 04 00 00 00 00 00 mask 1f 00 00 00 00 00, last read 12 00 00 00 1d 00"));
    CHECK_THAT(text, Catch::Contains("AL status PREOP+ERR, code 0x001d (invalid output configuration)"));
    // The polls stopped at the Validate timeout: about one read per poll interval, never more.
    CHECK(bus.requests().size() <= 200 + 3);
}

TEST_CASE("Retries repeat a command after timeouts", "[sequencer][initcmd]") {
    int calls = 0;
    ScriptedBus bus([&calls](const bus::DatagramRequest&) {
        return ++calls <= 2 ? bus_error(bus::BusErrc::Timeout) : reply({0x02, 0x00}, 1);
    });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);

    SECTION("enough retries") {
        REQUIRE(runner.run(write_al_control(2), drive()));
        CHECK(calls == 3);
        for (const auto& r : bus.requests()) CHECK(r.retries == 0);  // the ENI's Retries are counted here, not twice
    }
    SECTION("too few retries") {
        const auto result = runner.run(write_al_control(1), drive());
        REQUIRE_FALSE(result);
        CHECK(result.error().failure == InitCmdFailure::Timeout);
        CHECK_THAT(result.error().describe(), Catch::Contains("no reply within 100 ms in 2 attempt(s)"));
        CHECK(calls == 2 + 1);  // two attempts, then one read of AL status for the message
    }
}

TEST_CASE("Cnt: a wrong WKC is retried and then reported", "[sequencer][initcmd]") {
    ScriptedBus bus([](const bus::DatagramRequest& r) {
        // AL control answers with WKC 0; the AL status read for the message works.
        return ado_of(r) == wire::reg::kAlStatus ? reply({0x01, 0, 0, 0, 0x11, 0}, 1) : reply({0x02, 0x00}, 0);
    });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    const auto result = runner.run(write_al_control(2), drive());
    REQUIRE_FALSE(result);
    CHECK(result.error().failure == InitCmdFailure::WkcMismatch);
    CHECK_THAT(result.error().describe(), Catch::Contains("WKC expected 1, received 0 after 3 attempt(s)"));
    CHECK_THAT(result.error().describe(), Catch::Contains("AL status INIT, code 0x0011 (invalid requested state change)"));
    CHECK(bus.requests().size() == 3 + 1);
}

TEST_CASE("No Cnt: any WKC is accepted", "[sequencer][initcmd]") {
    ScriptedBus bus([](const bus::DatagramRequest&) { return reply({0x00, 0x00}, 0); });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    auto cmd = write_al_control(3);
    cmd.expected_wkc.reset();
    REQUIRE(runner.run(cmd, drive()));
    CHECK(bus.requests().size() == 1);
}

TEST_CASE("The zero DC start time is replaced by the computed one", "[sequencer][initcmd][dc]") {
    constexpr std::uint64_t kSystemTime = 5'123'456'789;
    std::vector<std::uint8_t> written;
    ScriptedBus bus([&written](const bus::DatagramRequest& r) {
        if (ado_of(r) == wire::reg::kDcSystemTime) {
            std::vector<std::uint8_t> time(8, 0);
            store_le<std::uint64_t>(time, 0, kSystemTime);
            return reply(time, 1);
        }
        written = r.data;
        return reply(r.data, 1);
    });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    eni::EcatCmd cmd;
    cmd.comment = "set dc start time";
    cmd.command = wire::Command::Fpwr;
    cmd.adp = 1002;
    cmd.ado = wire::reg::kDcStartTime;
    cmd.data.assign(8, 0);
    cmd.expected_wkc = 1;
    auto context = drive();
    context.dc = dc::StartTimeParameters{bus::SlaveAddress::station(1001), 1'000'000, 250'000};

    REQUIRE(runner.run(cmd, context));
    const auto requests = bus.requests();
    REQUIRE(requests.size() == 2);
    CHECK(requests[0].command == wire::Command::Fprd);
    CHECK(adp_of(requests[0]) == 1001);  // the reference clock, not the slave being written
    REQUIRE(written.size() == 8);
    // 5.123456789 s + 100 ms, rounded up to the 1 ms cycle, plus the 250 us shift.
    CHECK(load_le<std::uint64_t>(written, 0) == 5'224'250'000ULL);

    SECTION("a start time that is not zeros goes out as written") {
        cmd.data = {1, 2, 3, 4, 0, 0, 0, 0};
        REQUIRE(runner.run(cmd, context));
        CHECK(written == cmd.data);
    }
}

TEST_CASE("Position-addressed commands move by the absent slaves ahead", "[sequencer][initcmd]") {
    ScriptedBus bus([](const bus::DatagramRequest& r) { return reply(r.data, 1); });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    eni::EcatCmd cmd;
    cmd.command = wire::Command::Apwr;
    cmd.adp = 0xFFFE;  // ring position 2 as the ENI writes it
    cmd.ado = wire::reg::kStationAddress;
    cmd.data = {0xeb, 0x03};
    auto context = drive();
    context.position_shift = 1;
    REQUIRE(runner.run(cmd, context));
    CHECK(adp_of(bus.requests().front()) == 0xFFFF);  // now at position 1

    cmd.command = wire::Command::Fpwr;  // station addressing is not moved
    cmd.adp = 1003;
    REQUIRE(runner.run(cmd, context));
    CHECK(adp_of(bus.requests().back()) == 1003);
}

TEST_CASE("A refusal of the bus ends the command at once", "[sequencer][initcmd]") {
    ScriptedBus bus([](const bus::DatagramRequest&) { return bus_error(bus::BusErrc::MasterRedStateInactive); });
    VirtualClock clock;
    InitCmdRunner runner(bus, clock);
    const auto result = runner.run(write_al_control(5), drive());
    REQUIRE_FALSE(result);
    CHECK(result.error().failure == InitCmdFailure::Bus);
    CHECK(result.error().bus_error == bus::BusErrc::MasterRedStateInactive);
    CHECK(bus.requests().size() == 1);
}

TEST_CASE("requested_al_state finds AL control writes", "[sequencer][initcmd]") {
    auto cmd = write_al_control(0);
    CHECK(sequencer::requested_al_state(cmd) == std::uint8_t{2});
    cmd.data = {0x11, 0x00};
    CHECK(sequencer::requested_al_state(cmd) == std::uint8_t{1});
    cmd.command = wire::Command::Fprd;
    CHECK_FALSE(sequencer::requested_al_state(cmd));
    cmd = write_al_control(0);
    cmd.ado = wire::reg::kAlStatus;
    CHECK_FALSE(sequencer::requested_al_state(cmd));
}

}  // namespace
}  // namespace ecpair::test
