// compare_with_eni on hand-made scan reports: the mismatch descriptors
// (missing, extra, wrong product, wrong alias / explicit device ID) and
// presence with Hot-Connect groups.

#include <catch2/catch.hpp>

#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/eni/loader.hpp"

namespace ecpair::test {
namespace {

using bus::SlaveMatch;

eni::Slave configured(const std::string& name, std::uint16_t phys, std::uint16_t position, std::uint32_t product) {
    eni::Slave s;
    s.info.name = name;
    s.info.phys_addr = phys;
    s.info.ring_position = position;
    s.info.vendor_id = 2;
    s.info.product_code = product;
    s.info.revision_no = 0x00100000;
    return s;
}

bus::ScannedSlave found(std::uint16_t position, std::uint32_t product, std::uint32_t vendor = 2) {
    bus::ScannedSlave s;
    s.position = position;
    s.identity = bus::SlaveIdentity{vendor, product, 0x00100000, 0};
    return s;
}

eni::EniConfig three_slaves() {
    eni::EniConfig eni;
    eni.slaves = {configured("S1", 1001, 0, 0x1111), configured("S2", 1002, 1, 0x2222), configured("S3", 1003, 2, 0x3333)};
    return eni;
}

bus::ScanReport report_of(std::vector<bus::ScannedSlave> slaves) {
    bus::ScanReport report;
    report.responding = static_cast<std::uint16_t>(slaves.size());
    report.slaves = std::move(slaves);
    return report;
}

TEST_CASE("A bus as configured matches", "[sequencer][scan]") {
    const auto eni = three_slaves();
    const auto report = report_of({found(0, 0x1111), found(1, 0x2222), found(2, 0x3333)});
    const auto result = bus::compare_with_eni(report, eni);
    REQUIRE(result.size() == 3);
    CHECK(bus::all_match(result));
    CHECK(result[2].configured_index == std::size_t{2});
    CHECK(result[2].found == &report.slaves[2]);
}

TEST_CASE("A missing slave is reported with where it should hang", "[sequencer][scan]") {
    const auto eni = three_slaves();
    const auto report = report_of({found(0, 0x1111), found(1, 0x2222)});
    const auto result = bus::compare_with_eni(report, eni);
    CHECK_FALSE(bus::all_match(result));
    REQUIRE(result.size() == 3);
    CHECK(result[2].match == SlaveMatch::Missing);
    CHECK(result[2].describe() ==
          "position 2 (after station 1002): configured 'S3' vendor 0x00000002 product 0x00003333 revision "
          "0x00100000 serial 0, found nothing");
}

TEST_CASE("An extra slave is unexpected", "[sequencer][scan]") {
    const auto eni = three_slaves();
    const auto report = report_of({found(0, 0x1111), found(1, 0x2222), found(2, 0x3333), found(3, 0x4444, 7)});
    const auto result = bus::compare_with_eni(report, eni);
    CHECK_FALSE(bus::all_match(result));
    REQUIRE(result.size() == 4);
    CHECK(result[3].match == SlaveMatch::Unexpected);
    CHECK(result[3].previous_station == std::uint16_t{1003});
    CHECK_THAT(result[3].describe(), Catch::Contains("position 3 (after station 1003): unexpected: configured nothing, "
                                                     "found vendor 0x00000007 product 0x00004444"));
}

TEST_CASE("A wrong product is a wrong identity, with the PreviousPort in the descriptor", "[sequencer][scan]") {
    auto eni = three_slaves();
    eni.slaves[1].previous_ports.push_back(eni::PreviousPort{true, 'B', 1001});
    const auto report = report_of({found(0, 0x1111), found(1, 0x9999), found(2, 0x3333)});
    const auto result = bus::compare_with_eni(report, eni);
    CHECK_FALSE(bus::all_match(result));
    CHECK(result[1].match == SlaveMatch::WrongIdentity);
    CHECK_THAT(result[1].describe(),
               Catch::Contains("position 1 (after station 1001 port B): wrong identity: configured 'S2'") &&
                   Catch::Contains("product 0x00002222") && Catch::Contains("found vendor 0x00000002 product 0x00009999"));
}

TEST_CASE("Identification: station alias and explicit device ID", "[sequencer][scan]") {
    auto eni = three_slaves();
    SECTION("alias") {
        eni.slaves[1].info.identification = eni::Identification{bus::kIdentificationAlias, 7};
        auto report = report_of({found(0, 0x1111), found(1, 0x2222), found(2, 0x3333)});
        report.slaves[1].alias = 5;
        auto result = bus::compare_with_eni(report, eni);
        CHECK(result[1].match == SlaveMatch::WrongIdentification);
        CHECK_THAT(result[1].describe(), Catch::Contains("station alias (0x0012) expected 7, read 5"));
        report.slaves[1].alias = 7;
        result = bus::compare_with_eni(report, eni);
        CHECK(bus::all_match(result));
    }
    SECTION("explicit device ID") {
        eni.slaves[2].info.identification = eni::Identification{bus::kIdentificationExplicitId, 42};
        const auto report = report_of({found(0, 0x1111), found(1, 0x2222), found(2, 0x3333)});
        bus::IdentificationReadings readings;
        readings.explicit_device_ids = {std::nullopt, std::nullopt, std::uint16_t{41}};
        auto result = bus::compare_with_eni(report, eni, readings);
        CHECK(result[2].match == SlaveMatch::WrongIdentification);
        CHECK_THAT(result[2].describe(), Catch::Contains("explicit device ID (0x0134) expected 42, read 41"));
        readings.explicit_device_ids[2] = 42;
        CHECK(bus::all_match(bus::compare_with_eni(report, eni, readings)));
        readings.explicit_device_ids.clear();  // not readable
        result = bus::compare_with_eni(report, eni, readings);
        CHECK_THAT(result[2].describe(), Catch::Contains("expected 42, read nothing readable"));
    }
    SECTION("value 0 is not checked") {
        eni.slaves[1].info.identification = eni::Identification{bus::kIdentificationExplicitId, 0};
        const auto report = report_of({found(0, 0x1111), found(1, 0x2222), found(2, 0x3333)});
        CHECK(bus::all_match(bus::compare_with_eni(report, eni)));
    }
}

class HotConnectEni {
public:
    HotConnectEni() {
        auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_extra/hotconnect_groups_4slaves.xml"));
        REQUIRE(loaded);
        eni = *loaded;
    }
    // The slave as the bus shows it, with the identification value the ENI expects.
    bus::ScannedSlave found_as(std::size_t slave, std::uint16_t position) {
        const auto& info = eni->slaves[slave].info;
        bus::ScannedSlave s;
        s.position = position;
        s.identity = bus::SlaveIdentity{info.vendor_id, info.product_code, info.revision_no, 0};
        if (info.identification && info.identification->ado == bus::kIdentificationAlias) s.alias = *info.identification->value;
        if (info.identification && info.identification->ado == bus::kIdentificationExplicitId) {
            readings.explicit_device_ids.resize(std::max<std::size_t>(readings.explicit_device_ids.size(), position + 1u));
            readings.explicit_device_ids[position] = *info.identification->value;
        }
        return s;
    }
    std::vector<bus::SlaveComparison> compare(const bus::ScanReport& report) const {
        return bus::compare_with_eni(report, *eni, readings);
    }
    std::shared_ptr<const eni::EniConfig> eni;
    bus::IdentificationReadings readings;
};

TEST_CASE_METHOD(HotConnectEni, "An absent Hot-Connect group is optional and takes no position", "[sequencer][scan]") {
    // Coupler, then the tool changer right behind it: the gripper group (2 slaves) is not plugged in.
    const auto report = report_of({found_as(0, 0), found_as(3, 1)});
    const auto result = compare(report);
    REQUIRE(result.size() == 4);
    CHECK(bus::all_match(result));
    CHECK(result[1].match == SlaveMatch::Absent);
    CHECK(result[1].optional);
    CHECK(result[2].match == SlaveMatch::Absent);
    CHECK(result[3].match == SlaveMatch::Match);
    CHECK(result[3].position == 1);
    CHECK_THAT(result[1].describe(), Catch::Contains("optional 'Gripper drive'") && Catch::Contains("is absent"));
}

TEST_CASE_METHOD(HotConnectEni, "Hot-Connect groups present, absent, or present but incomplete", "[sequencer][scan]") {
    SECTION("everything present") {
        const auto report = report_of({found_as(0, 0), found_as(1, 1), found_as(2, 2), found_as(3, 3)});
        CHECK(bus::all_match(compare(report)));
    }
    SECTION("all optional slaves absent") {
        const auto report = report_of({found_as(0, 0)});
        CHECK(bus::all_match(compare(report)));
    }
    SECTION("the head is there but its member is not: a mismatch") {
        const auto report = report_of({found_as(0, 0), found_as(1, 1), found_as(3, 2)});
        const auto result = compare(report);
        CHECK_FALSE(bus::all_match(result));
        CHECK(result[2].match == SlaveMatch::WrongIdentity);
    }
    SECTION("a mandatory slave missing is a mismatch") {
        const auto report = report_of({found_as(3, 0)});
        const auto result = compare(report);
        CHECK_FALSE(bus::all_match(result));
        CHECK(result[0].match == SlaveMatch::WrongIdentity);
    }
}

}  // namespace
}  // namespace ecpair::test
