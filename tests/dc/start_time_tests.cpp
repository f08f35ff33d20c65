// The SYNC0 start time: its arithmetic and whose system time it is taken
// from (one rule for start-up and Hot-Connect).

#include <catch2/catch.hpp>

#include "ecpair/dc/start_time.hpp"

using namespace ecpair;

TEST_CASE("DC start time arithmetic", "[dc]") {
    using std::chrono::milliseconds;
    CHECK(dc::start_time(0, milliseconds(100), 1'000'000, 0) == 100'000'000);
    CHECK(dc::start_time(1, milliseconds(100), 1'000'000, 0) == 101'000'000);
    CHECK(dc::start_time(1, milliseconds(100), 1'000'000, -300'000) == 100'700'000);
    CHECK(dc::start_time(7, milliseconds(0), 0, 0) == 7);
}

TEST_CASE("the start time's reference clock and cycle", "[dc]") {
    eni::EniConfig eni;
    eni.slaves.resize(3);
    for (std::uint16_t i = 0; i < 3; ++i) eni.slaves[i].info.phys_addr = static_cast<std::uint16_t>(1001 + i);
    eni.slaves[1].dc = eni::DistributedClocks{};
    eni.slaves[2].dc = eni::DistributedClocks{};
    eni.slaves[2].dc->cycle_time0_ns = 500'000;
    eni.slaves[2].dc->shift_time_ns = 2'000;
    const auto reference_of = [&eni](std::vector<bool> present) -> std::optional<std::uint16_t> {
        const auto p = dc::start_time_parameters(eni, 2, present);
        if (!p) return std::nullopt;
        return p->reference_clock.value;
    };
    CHECK(reference_of({true, true, true}) == 1002);  // the first with a <DC> element
    eni.slaves[2].dc->reference_clock = true;
    CHECK(reference_of({true, true, true}) == 1003);   // the marked one
    CHECK(reference_of({true, true, false}) == 1002);  // the marked one is absent
    const auto p = dc::start_time_parameters(eni, 2, {true, true, true});
    CHECK(p->cycle_time_ns == 500'000);
    CHECK(p->shift_time_ns == 2'000);
    CHECK(p->reference_clock.mode == bus::SlaveAddress::Mode::Station);

    SECTION("no <DC> element: the first present slave; no cycle time of its own: the ENI's") {
        eni.slaves[1].dc.reset();
        eni.slaves[2].dc.reset();
        eni.cyclic.push_back(eni::Cyclic{2000, {}});
        CHECK(reference_of({false, true, true}) == 1002);
        CHECK_FALSE(reference_of({false, false, false}));
        CHECK(dc::start_time_parameters(eni, 0, {true, true, true})->cycle_time_ns == 2'000'000);
    }
}

TEST_CASE("which InitCmds carry the start time", "[dc]") {
    eni::EcatCmd cmd;
    cmd.command = wire::Command::Fpwr;
    cmd.ado = 0x0990;
    cmd.data.assign(8, 0);
    CHECK(dc::is_zero_start_time_write(cmd));
    cmd.data[3] = 1;
    CHECK_FALSE(dc::is_zero_start_time_write(cmd));
    cmd.data[3] = 0;
    cmd.command = wire::Command::Fprd;
    CHECK_FALSE(dc::is_zero_start_time_write(cmd));
}
