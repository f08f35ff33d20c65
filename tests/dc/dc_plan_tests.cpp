// The DC plan from ENI models and from the shared drive ENIs: which slaves
// run in DC mode, the reference clock, and the settings that cannot work.

#include <catch2/catch.hpp>

#include <fmt/format.h>

#include "ecpair/dc/dc_plan.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/wire/esc_registers.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

eni::EniConfig slaves(std::size_t count) {
    eni::EniConfig eni;
    eni.source_path = "plan.xml";
    eni.slaves.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        eni.slaves[i].info.name = fmt::format("S{}", i);
        eni.slaves[i].info.phys_addr = static_cast<std::uint16_t>(1001 + i);
        eni.slaves[i].source_line = static_cast<int>(10 * (i + 1));
    }
    return eni;
}

eni::DistributedClocks sync0(std::uint32_t cycle, bool reference = false) {
    eni::DistributedClocks dc;
    dc.cycle_time0_ns = cycle;
    dc.shift_time_ns = 0;
    dc.reference_clock = reference;
    return dc;
}

std::shared_ptr<const eni::EniConfig> load(const char* name) {
    auto eni = eni::load_eni_file(fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, name));
    REQUIRE(eni);
    return *eni;
}

}  // namespace

TEST_CASE("the shared drive ENIs: every drive in DC mode, the first one the reference", "[dc]") {
    const auto elmo = load("ecengineer_rocos_elmo_4slaves.xml");
    const auto plan = dc::DcPlan::build(*elmo, 1ms);
    REQUIRE(plan);
    CHECK(plan->used());
    CHECK(plan->slaves().size() == 4);
    CHECK(plan->slaves().front().sync0_cycle_ns == 1'000'000);
    CHECK(plan->reference({true, true, true, true}) == std::size_t{0});
    CHECK(plan->reference({false, true, true, true}) == std::size_t{1});

    const auto twincat = load("twincat_kpierczy_5slaves.xml");
    const auto tc = dc::DcPlan::build(*twincat, 10ms);
    REQUIRE(tc);
    CHECK(tc->slaves().size() == 4);
    CHECK(tc->reference(std::vector<bool>(5, true)) == std::size_t{1});  // the IMU at position 0 has no DC

    const auto io = load("advantech_io_ring_4slaves.xml");
    const auto none = dc::DcPlan::build(*io, 1ms);
    REQUIRE(none);
    CHECK_FALSE(none->used());
}

TEST_CASE("a bus cycle that is not a whole multiple of SYNC0 is refused, naming the slave and line", "[dc]") {
    auto eni = slaves(2);
    eni.slaves[0].dc = sync0(1'000'000, true);
    eni.slaves[1].dc = sync0(300'000);
    const auto plan = dc::DcPlan::build(eni, 1ms);
    REQUIRE_FALSE(plan);
    CHECK_THAT(plan.error(), Catch::Contains("plan.xml:20"));
    CHECK_THAT(plan.error(), Catch::Contains("slave 'S1' (station 1002)"));
    CHECK_THAT(plan.error(), Catch::Contains("300000 ns"));
    CHECK(dc::DcPlan::build(eni, 3ms));  // 3 ms is a multiple of 300 us and of 1 ms
    eni.slaves[1].dc->cycle_time0_ns = 500'000;
    CHECK(dc::DcPlan::build(eni, 1ms));  // two SYNC0 pulses per cycle
}

TEST_CASE("a slave in DC mode ahead of the reference clock is refused", "[dc]") {
    auto eni = slaves(3);
    eni.slaves[0].dc = sync0(1'000'000);
    eni.slaves[2].dc = sync0(1'000'000, true);
    const auto plan = dc::DcPlan::build(eni, 1ms);
    REQUIRE_FALSE(plan);
    CHECK_THAT(plan.error(), Catch::Contains("plan.xml:10"));
    CHECK_THAT(plan.error(), Catch::Contains("comes before the reference clock slave 'S2'"));
}

TEST_CASE("DC mode switched on by InitCmds without a <DC> element", "[dc]") {
    auto eni = slaves(2);
    eni::EcatCmd cycle;
    cycle.command = wire::Command::Fpwr;
    cycle.ado = wire::reg::kDcCycleTime0;
    cycle.data = {0x40, 0x42, 0x0f, 0x00};  // 1 ms
    eni::EcatCmd activation;
    activation.command = wire::Command::Fpwr;
    activation.ado = wire::reg::kDcCycleUnitControl;
    activation.data = {0x00, 0x03};
    activation.source_line = 99;
    eni.slaves[1].init_cmds = {cycle, activation};
    const auto plan = dc::DcPlan::build(eni, 1ms);
    REQUIRE(plan);
    REQUIRE(plan->slaves().size() == 1);
    CHECK(plan->slaves()[0].index == 1);
    CHECK(plan->slaves()[0].sync0_cycle_ns == 1'000'000);
    CHECK(plan->slaves()[0].source_line == 99);
    CHECK(plan->reference({true, true}) == std::size_t{0});  // no <DC> anywhere: the first slave
    CHECK_FALSE(dc::DcPlan::build(eni, 1500us));
}
