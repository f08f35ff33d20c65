// LinkAdmin on a veth cable in a network namespace: setting one end down
// takes the carrier from both ends (the other end's monitor sees it), up
// brings it back; the administrative flag reads back; a missing interface
// is named in the error.

#include "ecpair/link/link_admin.hpp"
#include "link_netns_fixture.hpp"

using ecpair::link::LinkAdmin;
using ecpair::link::LinkErrc;
using ecpair::link::test::VethFixture;

namespace {

std::unique_ptr<LinkAdmin> open_admin(const ecpair::test::TestNamespace& ns) {
    ecpair::test::NamespaceScope inside(ns);
    auto opened = LinkAdmin::open();
    if (!opened) FAIL(opened.error().message);
    return std::move(opened).value();
}

}  // namespace

TEST_CASE_METHOD(VethFixture, "link admin: down takes the carrier from both ends, up restores it", "[link][admin]") {
    auto admin = open_admin(ns);
    REQUIRE(admin->is_up("ecm0").value() == true);

    REQUIRE(admin->set_up("ecm0", false));
    CHECK(admin->is_up("ecm0").value() == false);
    CHECK(admin->is_up("ecs0").value() == true);  // the far end stays up, without carrier
    await_state({"ecm0", "ecs0"}, false);

    REQUIRE(admin->set_up("ecm0", false));  // already down: still fine
    REQUIRE(admin->set_up("ecm0", true));
    CHECK(admin->is_up("ecm0").value() == true);
    await_state({"ecm0", "ecs0"}, true);
}

TEST_CASE_METHOD(VethFixture, "link admin: a missing interface is named in the error", "[link][admin]") {
    auto admin = open_admin(ns);
    auto set = admin->set_up("ecnothere0", false);
    REQUIRE_FALSE(set);
    CHECK(set.error().code == LinkErrc::InterfaceNotFound);
    CHECK(set.error().message.find("ecnothere0") != std::string::npos);
    auto read = admin->is_up("ecnothere0");
    REQUIRE_FALSE(read);
    CHECK(read.error().code == LinkErrc::InterfaceNotFound);
    auto too_long = admin->set_up("a-name-far-too-long-for-linux", true);
    REQUIRE_FALSE(too_long);
    CHECK(too_long.error().message.find("a-name-far-too-long-for-linux") != std::string::npos);
}
