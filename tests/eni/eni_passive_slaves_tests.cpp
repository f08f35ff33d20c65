// A <Slave> without PhysAddr, AutoIncAddr and InitCmds (the EL9011 end cap
// of a TwinCAT 2 export) is a passive terminal: kept apart from the ring's
// slaves, with a warning. One that names an unknown slave in its
// PreviousPort, or has process data, is refused.

#include <fstream>
#include <iterator>

#include "eni_test_files.hpp"

namespace ecpair::eni {

using test::extra_eni;
using test::must_load;

TEST_CASE("a slave without PhysAddr, AutoIncAddr and InitCmds is a passive terminal", "[eni][extra]") {
    const auto eni = must_load(extra_eni("passive_end_cap_4slaves.xml"));
    REQUIRE(eni->slaves.size() == 3);
    CHECK(eni->slaves[2].info.name == "Term 3 (EL2008)");
    CHECK(eni->slaves[2].info.ring_position == 2);
    REQUIRE(eni->passive_slaves.size() == 1);
    const auto& cap = eni->passive_slaves[0];
    CHECK(cap.name == "Term 4 (EL9011)");
    CHECK(cap.vendor_id == std::uint32_t{2});
    CHECK(cap.product_code == std::uint32_t{0x23333052});
    CHECK(cap.file_index == 3);
    REQUIRE(cap.previous_ports.size() == 1);
    CHECK(cap.previous_ports[0].port == 'B');
    CHECK(cap.previous_ports[0].phys_addr == 1003);
}

TEST_CASE("a passive slave naming an unknown slave, or with process data, is refused", "[eni][extra]") {
    const auto eni_text = [](const std::string& from, const std::string& to) {
        std::ifstream in(extra_eni("passive_end_cap_4slaves.xml"));
        std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto at = xml.rfind(from);
        REQUIRE(at != std::string::npos);
        xml.replace(at, from.size(), to);
        return xml;
    };
    // The passive slave is the file's last: the last PhysAddr 1003 is its PreviousPort's, the last </Info> its own.
    const auto unknown = load_eni_string(eni_text("<PhysAddr>1003</PhysAddr>", "<PhysAddr>1009</PhysAddr>"), "t.xml");
    REQUIRE_FALSE(unknown);
    CHECK_THAT(unknown.error().message, Catch::Contains("no slave in this file has PhysAddr 1009"));
    const auto with_data = load_eni_string(
        eni_text("</Info>", "</Info><ProcessData><Recv><BitStart>0</BitStart><BitLength>8</BitLength></Recv></ProcessData>"),
        "t.xml");
    REQUIRE_FALSE(with_data);
    CHECK_THAT(with_data.error().message, Catch::Contains("has no ESC (a passive terminal) and cannot exchange process data"));
}

}  // namespace ecpair::eni
