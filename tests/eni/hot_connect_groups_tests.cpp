// Hot-Connect groups as the ENI defines them: members, the mandatory group,
// pinned and floating groups, the identification of a head, where each
// slave hangs, and the rules the loader enforces (members behind their
// head, no group in a group, no mandatory slave behind an optional one).

#include <fstream>
#include <sstream>

#include "ecpair/eni/eni_topology.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/eni/identification.hpp"
#include "eni_test_files.hpp"

namespace ecpair::eni {
namespace {

using test::extra_eni;
using test::must_load;

std::string text_of(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The 4-slave Hot-Connect file with one piece of text replaced (it must be there).
std::string edited(const std::string& from, const std::string& to) {
    auto xml = text_of(extra_eni("hotconnect_groups_4slaves.xml"));
    const auto at = xml.find(from);
    REQUIRE(at != std::string::npos);
    xml.replace(at, from.size(), to);
    return xml;
}

std::string load_error(const std::string& xml) {
    const auto result = load_eni_string(xml, "groups.xml");
    REQUIRE_FALSE(result);
    return result.error().describe();
}

TEST_CASE("groups of the 4-slave Hot-Connect file", "[eni][hotconnect]") {
    const auto eni = must_load(extra_eni("hotconnect_groups_4slaves.xml"));
    const auto groups = HotConnectGroups::of(*eni);
    REQUIRE(groups.groups().size() == 3);
    CHECK(groups.optional_count() == 2);
    CHECK(groups.group(0).members == std::vector<std::size_t>{0});
    CHECK(groups.group(1).name == "Gripper");
    CHECK(groups.group(1).head == std::size_t{1});
    CHECK(groups.group(1).members == std::vector<std::size_t>{1, 2});
    CHECK(groups.group(2).members == std::vector<std::size_t>{3});
    CHECK(groups.group_of(2) == 1);
    CHECK(groups.is_head(1));
    CHECK_FALSE(groups.is_head(2));
    CHECK_FALSE(groups.is_optional(0));
    CHECK_FALSE(groups.group(1).floating);

    const auto topology = EniTopology::of(*eni);
    CHECK_FALSE(topology.attachment(0));
    CHECK(topology.attachment(1) == Attachment{0, 1});
    CHECK(topology.attachment(2) == Attachment{1, 1});
    CHECK(topology.attachment(3) == Attachment{0, 2});
    CHECK(topology.child(0, 2) == std::size_t{3});
    CHECK_FALSE(topology.child(0, 3));
}

TEST_CASE("a group head without PreviousPort in a file that uses them floats", "[eni][hotconnect]") {
    const auto xml = edited("<PreviousPort Selected=\"1\">\n        <Port>C</Port>\n        <PhysAddr>1001</PhysAddr>\n      </PreviousPort>", "");
    const auto eni = load_eni_string(xml, "floating.xml");
    REQUIRE(eni);
    const auto groups = HotConnectGroups::of(**eni);
    CHECK(groups.group(2).floating);
    CHECK_FALSE(EniTopology::of(**eni).attachment(3));
    CHECK(EniTopology::of(**eni).floating(3));
}

TEST_CASE("identification modes from Info/Identification", "[eni][hotconnect]") {
    Slave s;
    CHECK(identification_of(s).mode == IdentificationMode::None);
    s.info.identification = Identification{0x0012, 7, true};
    CHECK(identification_of(s) == IdentificationSpec{IdentificationMode::StationAlias, 0x0012, 7});
    s.info.identification = Identification{0x0134, 9, true};
    CHECK(identification_of(s).mode == IdentificationMode::ExplicitDeviceId);
    s.info.identification = Identification{0x1402, 9, true};
    CHECK(identification_of(s).mode == IdentificationMode::InputWord);
    s.info.identification = Identification{0x0f10, 9, true};
    CHECK(identification_of(s).mode == IdentificationMode::Register);
    s.info.identification = Identification{0x0012, 0, true};
    CHECK(identification_of(s).mode == IdentificationMode::None);  // Value 0: not checked
    s.info.identification = Identification{0x0012, 5, false};
    CHECK(identification_of(s).mode == IdentificationMode::None);  // EnableIdentification="False"
}

TEST_CASE("the loader refuses groups that break the rules", "[eni][hotconnect]") {
    SECTION("more members than slaves follow") {
        const auto error = load_error(edited("<GroupMemberCnt>2</GroupMemberCnt>", "<GroupMemberCnt>5</GroupMemberCnt>"));
        CHECK_THAT(error, Catch::Contains("groups.xml:") && Catch::Contains("GroupMemberCnt") &&
                              Catch::Contains("GroupMemberCnt is 5, but only 3 slave(s) from 'Gripper drive' "
                                              "(PhysAddr 1002) on are left in ring order"));
    }
    SECTION("a group inside a group") {
        const auto error = load_error(edited("<GroupMemberCnt>2</GroupMemberCnt>", "<GroupMemberCnt>3</GroupMemberCnt>"));
        CHECK_THAT(error, Catch::Contains("'Tool changer' (PhysAddr 1004) heads a Hot-Connect group but is itself a "
                                          "member of the group of 'Gripper drive' (PhysAddr 1002)"));
    }
    SECTION("a member hanging outside its group") {
        const auto error = load_error(edited("<Port>B</Port>\n        <PhysAddr>1002</PhysAddr>",
                                             "<Port>D</Port>\n        <PhysAddr>1001</PhysAddr>"));
        CHECK_THAT(error, Catch::Contains("'Gripper IO' (PhysAddr 1003) is a member of the Hot-Connect group of "
                                          "'Gripper drive' (PhysAddr 1002) but hangs on 'Coupler' (PhysAddr 1001)"));
    }
    SECTION("a mandatory slave behind an optional group") {
        auto xml = edited("<Port>C</Port>\n        <PhysAddr>1001</PhysAddr>", "<Port>B</Port>\n        <PhysAddr>1003</PhysAddr>");
        const auto hc = xml.rfind("<HotConnect>");
        xml.erase(hc, xml.find("</HotConnect>", hc) + 13 - hc);
        const auto error = load_error(xml);
        CHECK_THAT(error, Catch::Contains("mandatory slave 'Tool changer' (PhysAddr 1004) hangs on 'Gripper IO' "
                                          "(PhysAddr 1003), a member of the optional Hot-Connect group of "
                                          "'Gripper drive' (PhysAddr 1002)"));
    }
}

}  // namespace
}  // namespace ecpair::eni
