// LinkStateMonitor on a veth cable in a network namespace: the initial state
// from the dump, transitions as they happen (each once), the watch list, and
// interfaces that disappear or appear.

#include "link_netns_fixture.hpp"

using ecpair::link::LinkStateChange;
using ecpair::link::LinkStateMonitor;
using ecpair::link::test::VethFixture;

namespace {

std::vector<LinkStateChange> changes_of(const std::vector<LinkStateChange>& changes, const std::string& name) {
    std::vector<LinkStateChange> selected;
    for (const auto& change : changes) {
        if (change.interface == name) selected.push_back(change);
    }
    return selected;
}

}  // namespace

TEST_CASE_METHOD(VethFixture, "link monitor: knows the initial state of watched interfaces only", "[link][monitor]") {
    CHECK(monitor->is_up("ecm0") == true);
    CHECK(monitor->is_up("ecs0") == true);
    CHECK_FALSE(monitor->is_up("lo").has_value());  // not watched
    CHECK(monitor->read_changes().empty());
}

TEST_CASE_METHOD(VethFixture, "link monitor: reports down and up, once per transition", "[link][monitor]") {
    ns.set_link("ecm0", false);
    auto down = await_state({"ecm0", "ecs0"}, false);
    REQUIRE(changes_of(down, "ecm0").size() == 1);
    REQUIRE(changes_of(down, "ecs0").size() == 1);
    CHECK_FALSE(changes_of(down, "ecm0")[0].up);
    CHECK_FALSE(changes_of(down, "ecs0")[0].up);

    ns.set_link("ecm0", true);
    auto up = await_state({"ecm0", "ecs0"}, true);
    REQUIRE(changes_of(up, "ecm0").size() == 1);
    REQUIRE(changes_of(up, "ecs0").size() == 1);
    CHECK(changes_of(up, "ecm0")[0].up);
    CHECK(changes_of(up, "ecm0")[0].timestamp >= changes_of(down, "ecm0")[0].timestamp);
}

TEST_CASE_METHOD(VethFixture, "link monitor: a deleted interface is reported down and becomes unknown",
                 "[link][monitor]") {
    REQUIRE(ns.exec("ip link del ecm0") == 0);
    auto gone = await_state({"ecm0", "ecs0"}, false);
    CHECK(changes_of(gone, "ecm0").size() == 1);
    CHECK_FALSE(monitor->is_up("ecm0").has_value());
    CHECK_FALSE(monitor->is_up("ecs0").has_value());
}

TEST_CASE_METHOD(VethFixture, "link monitor: an interface created later is picked up", "[link][monitor]") {
    std::unique_ptr<LinkStateMonitor> watching_new;
    {
        ecpair::test::NamespaceScope inside(ns);
        auto opened = LinkStateMonitor::open({"ecx0"});
        REQUIRE(opened);
        watching_new = std::move(opened).value();
    }
    CHECK_FALSE(watching_new->is_up("ecx0").has_value());
    ns.create_veth("ecx0", "ecx1");
    std::swap(monitor, watching_new);  // let await_state watch the new monitor
    auto appeared = await_state({"ecx0"}, true);
    CHECK(changes_of(appeared, "ecx0").size() == 1);
    CHECK(changes_of(appeared, "ecx1").empty());  // not watched
}

TEST_CASE("link monitor: watching every interface when none are named", "[link][monitor]") {
    ecpair::test::TestNamespace ns{"ecpt-link"};
    std::unique_ptr<LinkStateMonitor> monitor;
    {
        ecpair::test::NamespaceScope inside(ns);
        auto opened = LinkStateMonitor::open();
        REQUIRE(opened);
        monitor = std::move(opened).value();
    }
    CHECK(monitor->is_up("lo") == true);  // TestNamespace sets loopback up
}
