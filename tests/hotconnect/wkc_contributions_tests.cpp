// Expected WKCs that follow the slaves on the bus: BRD by the slaves that
// answer, LRD/LWR by the FMMUs of the slaves exchanging process data, LRW
// with read 1 + write 2, datagrams without <Cnt> left alone.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/hotconnect/wkc_contributions.hpp"
#include "ecpair/sim/eni_generator.hpp"

namespace ecpair::hotconnect {
namespace {

struct Generated {
    std::shared_ptr<const eni::EniConfig> eni;
    master::CyclicPlan plan;
};

Generated generated() {
    sim::GeneratedEniOptions o;
    o.slaves = 3;
    o.groups = 1;
    o.group_slaves = 2;
    o.input_bytes = 4;
    o.output_bytes = 4;
    auto eni = eni::load_eni_string(sim::generate_eni(o), "g.xml");
    REQUIRE(eni);
    auto plan = master::CyclicPlan::build(**eni, {});
    REQUIRE(plan);
    return {*eni, std::move(*plan)};
}

TEST_CASE("LWR/LRD and BRD follow the bus", "[hotconnect]") {
    const auto g = generated();
    const auto c = WkcContributions::of(*g.eni, g.plan);
    REQUIRE(c.datagrams().size() == 3);  // LWR, LRD, BRD
    CHECK(c.datagrams()[0].kind == ContributionKind::Logical);
    CHECK(c.datagrams()[2].kind == ContributionKind::Broadcast);

    BusCount all{std::vector<bool>(5, true), std::vector<bool>(5, true), 5};
    CHECK(c.expected(all) == std::vector<std::optional<std::uint16_t>>{5, 5, 5});

    // The group (ENI slaves 1 and 2) is gone.
    BusCount without{{true, false, false, true, true}, {true, false, false, true, true}, 3};
    CHECK(c.expected(without) == std::vector<std::optional<std::uint16_t>>{3, 3, 3});

    // The group answers (an unknown slave too), but does not run process data yet.
    BusCount joining{{true, false, false, true, true}, std::vector<bool>(5, true), 6};
    CHECK(c.expected(joining) == std::vector<std::optional<std::uint16_t>>{3, 3, 6});
}

TEST_CASE("LRW counts read 1 + write 2, split LRW as LWR + LRD, no Cnt stays unchecked", "[hotconnect]") {
    const auto eni = eni::load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_extra/hotconnect_groups_4slaves.xml"));
    REQUIRE(eni);
    auto plan = master::CyclicPlan::build(**eni, {});
    REQUIRE(plan);
    const auto c = WkcContributions::of(**eni, *plan);
    // This file has no FMMU InitCmds: the LRW's Cnt (6) stays as written, the BRD follows.
    BusCount two_gone{{true, false, false, true}, {true, false, false, true}, 2};
    const auto expected = c.expected(two_gone);
    REQUIRE(expected.size() == 2);
    CHECK(expected[0] == std::uint16_t{6});
    CHECK(expected[1] == std::uint16_t{2});
}

}  // namespace
}  // namespace ecpair::hotconnect
