// The startup scan over the simulated segment: a bus as configured, a
// missing, an extra and a wrong slave, alias and explicit device ID
// identification, and an absent Hot-Connect group.

#include <catch2/catch.hpp>

#include "ecpair/sequencer/startup_scan.hpp"
#include "fakes.hpp"
#include "segment_fixture.hpp"

namespace ecpair::test {
namespace {

using bus::SlaveMatch;

sequencer::ScanOutcome scan(sim::SegmentBusAccess& bus, const eni::EniConfig& eni) {
    VirtualClock clock;
    auto outcome = sequencer::StartupScan(bus, clock).run(eni);
    REQUIRE(outcome);
    return std::move(outcome).value();
}

TEST_CASE("Startup scan of a bus as configured", "[sequencer][scan][segment]") {
    const auto eni = load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml");
    SimulatedBus sim(*eni);
    const auto outcome = scan(sim.bus, *eni);
    CHECK(outcome.matches);
    CHECK(outcome.report.responding == 3);
    CHECK(outcome.present == std::vector<bool>{true, true, true});
    CHECK(outcome.position_shift == std::vector<std::uint16_t>{0, 0, 0});
}

TEST_CASE("Startup scan: missing, extra and wrong slaves", "[sequencer][scan][segment]") {
    const auto eni = load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml");

    SECTION("the last slave is missing") {
        auto wiring = std::make_shared<eni::EniConfig>(*eni);
        wiring->slaves.pop_back();
        SimulatedBus sim(*wiring);
        const auto outcome = scan(sim.bus, *eni);
        CHECK_FALSE(outcome.matches);
        const auto mismatches = outcome.mismatches();
        REQUIRE(mismatches.size() == 1);
        CHECK(mismatches[0]->match == SlaveMatch::Missing);
        CHECK_THAT(mismatches[0]->describe(), Catch::StartsWith("position 2 (after station 1002 port B): configured"));
    }
    SECTION("an unknown slave behind the last one") {
        SimulatedBus sim(*eni);
        REQUIRE(sim.segment.insert_unknown_slave(4));
        const auto outcome = scan(sim.bus, *eni);
        CHECK_FALSE(outcome.matches);
        const auto mismatches = outcome.mismatches();
        REQUIRE(mismatches.size() == 1);
        CHECK(mismatches[0]->match == SlaveMatch::Unexpected);
        CHECK(mismatches[0]->position == 3);
        CHECK_THAT(mismatches[0]->describe(), Catch::Contains("found vendor 0x0badc0de"));
    }
    SECTION("a different product at position 1") {
        auto wiring = std::make_shared<eni::EniConfig>(*eni);
        wiring->slaves[1].info.product_code += 1;
        SimulatedBus sim(*wiring);
        const auto outcome = scan(sim.bus, *eni);
        const auto mismatches = outcome.mismatches();
        REQUIRE(mismatches.size() == 1);
        CHECK(mismatches[0]->match == SlaveMatch::WrongIdentity);
        CHECK(mismatches[0]->position == 1);
        CHECK(mismatches[0]->configured_index == std::size_t{1});
    }
}

TEST_CASE("Startup scan: identification by station alias", "[sequencer][scan][segment]") {
    auto eni = load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml");
    eni->slaves[1].info.identification = eni::Identification{bus::kIdentificationAlias, 7};
    SimulatedBus sim(*eni);  // the simulated slave's EEPROM alias is the ENI's value
    CHECK(scan(sim.bus, *eni).matches);

    REQUIRE(sim.segment.set_eeprom_alias(2, 5));
    REQUIRE(sim.segment.power_off(2));  // the alias is loaded from the EEPROM at power-on
    REQUIRE(sim.segment.power_on(2));
    const auto outcome = scan(sim.bus, *eni);
    const auto mismatches = outcome.mismatches();
    REQUIRE(mismatches.size() == 1);
    CHECK(mismatches[0]->match == SlaveMatch::WrongIdentification);
    CHECK_THAT(mismatches[0]->describe(), Catch::Contains("station alias (0x0012) expected 7, read 5"));
}

TEST_CASE("Startup scan: identification by explicit device ID", "[sequencer][scan][segment]") {
    auto eni = load_eni_copy("ecengineer_rocos_elmo_3slaves_bcr.xml");
    eni->slaves[2].info.identification = eni::Identification{bus::kIdentificationExplicitId, 42};
    SimulatedBus sim(*eni);  // the simulated slave's ID selector is the ENI's value
    auto outcome = scan(sim.bus, *eni);
    CHECK(outcome.matches);
    REQUIRE(outcome.readings.explicit_device_ids.size() == 3);
    CHECK(outcome.readings.explicit_device_ids[2] == std::uint16_t{42});
    // The request was taken back: the slave shows no ID request any more.
    CHECK((sim.segment.slave(3).read_memory(0x0120, 1)[0] & 0x20) == 0);

    REQUIRE(sim.segment.set_id_selector(3, 41));
    outcome = scan(sim.bus, *eni);
    const auto mismatches = outcome.mismatches();
    REQUIRE(mismatches.size() == 1);
    CHECK_THAT(mismatches[0]->describe(), Catch::Contains("explicit device ID (0x0134) expected 42, read 41"));
}

TEST_CASE("Startup scan: an absent Hot-Connect group shifts the positions behind it", "[sequencer][scan][segment]") {
    const auto eni = load_eni_copy("eni_extra/hotconnect_groups_4slaves.xml");
    auto wiring = std::make_shared<eni::EniConfig>(*eni);
    wiring->slaves.erase(wiring->slaves.begin() + 1, wiring->slaves.begin() + 3);  // the gripper group
    SimulatedBus sim(*wiring);
    const auto outcome = scan(sim.bus, *eni);
    CHECK(outcome.matches);
    CHECK(outcome.present == std::vector<bool>{true, false, false, true});
    CHECK(outcome.position_shift == std::vector<std::uint16_t>{0, 0, 1, 2});
}

}  // namespace
}  // namespace ecpair::test
