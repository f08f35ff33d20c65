// match_topology on hand-made buses whose DL status tells the ports: a
// junction with a pinned group and a floating group, groups off and on, a
// floating group at another port, a pinned group at the wrong port, a
// duplicate, an unknown slave at a free port and one spliced into a cable,
// a group with the wrong identification or failing IdentifyCmds, and the
// fragment behind a line break.

#include <catch2/catch.hpp>

#include <map>
#include <set>

#include "ecpair/bus/topology_match.hpp"

namespace ecpair::test {
namespace {

using bus::GroupState;
using bus::SlaveMatch;

// J1 (1001) -- D: G1 "gripper" 1002 (alias 101) - B: 1003
//           -- B: J2 (1004) -- D: G2 "tool" 1005 (alias 102, pinned)
//                           -- B: 1006 (mandatory, last of the line)
// floating: G3 "probe" 1007 (alias 103), listed last, no PreviousPort.
// Ring order (everything plugged, G3 at J2 port C): J1 G1a G1b J2 G2 1006 G3.
eni::Slave slave(const std::string& name, std::uint16_t phys, std::uint16_t ring, std::uint32_t product) {
    eni::Slave s;
    s.info.name = name;
    s.info.phys_addr = phys;
    s.info.ring_position = ring;
    s.info.auto_inc_addr = static_cast<std::uint16_t>(0x10000 - ring);
    s.info.vendor_id = 0xE5C;
    s.info.product_code = product;
    s.info.revision_no = 1;
    return s;
}

void hang(eni::Slave& s, std::uint16_t parent, char port) { s.previous_ports.push_back(eni::PreviousPort{true, port, parent}); }

void head(eni::Slave& s, const std::string& group, std::uint32_t members, std::uint16_t alias) {
    s.hot_connect = eni::HotConnect{group, members, {}, 0};
    s.info.identification = eni::Identification{0x0012, alias, true};
}

eni::EniConfig junction_eni() {
    eni::EniConfig eni;
    auto j1 = slave("J1", 1001, 0, 0x100);
    auto g1a = slave("gripper", 1002, 1, 0x200);
    hang(g1a, 1001, 'D');
    head(g1a, "Gripper", 2, 101);
    auto g1b = slave("gripper IO", 1003, 2, 0x300);
    hang(g1b, 1002, 'B');
    auto j2 = slave("J2", 1004, 3, 0x100);
    hang(j2, 1001, 'B');
    auto g2 = slave("tool", 1005, 4, 0x400);
    hang(g2, 1004, 'D');
    head(g2, "Tool", 1, 102);
    auto last = slave("end", 1006, 5, 0x500);
    hang(last, 1004, 'B');
    auto g3 = slave("probe", 1007, 6, 0x400);  // the same device type as the tool
    head(g3, "Probe", 1, 103);
    eni.slaves = {j1, g1a, g1b, j2, g2, last, g3};
    return eni;
}

// A bus slave: identity of ENI slave `as`, alias, and the ports that lead on.
struct BusSlave {
    const eni::Slave* as = nullptr;
    std::uint16_t alias = 0;
    std::vector<int> downstream;  // ports with link and an open loop
    std::uint32_t vendor = 0;     // for unknown devices (as == nullptr)
};

std::uint16_t dl_status(const std::vector<int>& downstream) {
    std::uint16_t status = 0x0013;  // port 0 link, PDI operational
    for (int p = 1; p < 4; ++p) status = static_cast<std::uint16_t>(status | (1u << (8 + 2 * p)));  // closed
    for (const int p : downstream) {
        status = static_cast<std::uint16_t>(status | (1u << (4 + p)));
        status = static_cast<std::uint16_t>(status & ~(1u << (8 + 2 * p)));
    }
    return status;
}

bus::ScanReport bus_of(const std::vector<BusSlave>& slaves) {
    bus::ScanReport report;
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        bus::ScannedSlave s;
        s.position = static_cast<std::uint16_t>(i);
        if (slaves[i].as) {
            const auto& info = slaves[i].as->info;
            s.identity = bus::SlaveIdentity{info.vendor_id, info.product_code, info.revision_no, 0};
        } else {
            s.identity = bus::SlaveIdentity{slaves[i].vendor, 1, 1, 0};
        }
        s.alias = slaves[i].alias;
        s.dl_status = dl_status(slaves[i].downstream);
        s.dl_status_read = true;
        report.slaves.push_back(s);
    }
    report.responding = static_cast<std::uint16_t>(slaves.size());
    return report;
}

class FakeProbe final : public bus::IdentificationProbe {
public:
    std::optional<std::uint16_t> read(std::uint16_t position, const eni::IdentificationSpec&) override {
        const auto it = ids.find(position);
        return it == ids.end() ? std::nullopt : std::optional<std::uint16_t>(it->second);
    }
    bool identify_cmds_pass(std::uint16_t position, std::size_t) override { return !failing.contains(position); }
    std::map<std::uint16_t, std::uint16_t> ids;
    std::set<std::uint16_t> failing;
};

struct Fixture {
    eni::EniConfig eni = junction_eni();
    eni::HotConnectGroups groups = eni::HotConnectGroups::of(eni);
    FakeProbe probe;
    const eni::Slave& s(std::size_t i) const { return eni.slaves[i]; }

    bus::TopologyMatch match(const bus::ScanReport& report) { return bus::match_topology(report, eni, groups, probe); }
    static const bus::SlaveComparison& of(const bus::TopologyMatch& m, std::size_t configured) {
        for (const auto& c : m.comparisons) {
            if (c.configured_index == configured) return c;
        }
        FAIL("no comparison for slave " << configured);
        throw std::logic_error("unreachable");
    }
    static std::vector<const bus::SlaveComparison*> unexpected(const bus::TopologyMatch& m) {
        std::vector<const bus::SlaveComparison*> out;
        for (const auto& c : m.comparisons) {
            if (c.match == SlaveMatch::Unexpected) out.push_back(&c);
        }
        return out;
    }
};

TEST_CASE_METHOD(Fixture, "groups: the mandatory group, a pinned and a floating group", "[sequencer][hotconnect]") {
    REQUIRE(groups.groups().size() == 4);
    CHECK(groups.group(0).members == std::vector<std::size_t>{0, 3, 5});
    CHECK(groups.group(1).members == std::vector<std::size_t>{1, 2});
    CHECK_FALSE(groups.group(1).floating);
    CHECK_FALSE(groups.group(2).floating);
    CHECK(groups.group(3).floating);
    CHECK(groups.group(3).identification.mode == eni::IdentificationMode::StationAlias);
    CHECK(groups.group(3).identification.value == 103);
}

TEST_CASE_METHOD(Fixture, "every group plugged in where configured", "[sequencer][hotconnect]") {
    // J1 D->G1a B->G1b; J1 B->J2; J2 D->tool; J2 B->end; J2 C->probe (floating)
    const auto report = bus_of({{&s(0), 0, {3, 1}}, {&s(1), 101, {1}}, {&s(2), 0, {}}, {&s(3), 0, {3, 1, 2}},
                                {&s(4), 102, {}}, {&s(5), 0, {}}, {&s(6), 103, {}}});
    const auto m = match(report);
    CHECK_FALSE(m.blocking());
    CHECK(m.groups == std::vector<GroupState>{GroupState::Present, GroupState::Present, GroupState::Present,
                                              GroupState::Present});
    CHECK(m.position[6] == std::uint16_t{6});
    CHECK(of(m, 6).previous_station == std::uint16_t{1004});
    CHECK(of(m, 6).previous_port == 'C');
    CHECK(m.present() == std::vector<bool>(7, true));
}

TEST_CASE_METHOD(Fixture, "optional groups off: absent, the mandatory slaves shift up", "[sequencer][hotconnect]") {
    const auto report = bus_of({{&s(0), 0, {1}}, {&s(3), 0, {1}}, {&s(5), 0, {}}});
    const auto m = match(report);
    CHECK_FALSE(m.blocking());
    CHECK(m.groups[1] == GroupState::Absent);
    CHECK(m.groups[2] == GroupState::Absent);
    CHECK(m.groups[3] == GroupState::Absent);
    CHECK(m.position[3] == std::uint16_t{1});
    CHECK(m.position[5] == std::uint16_t{2});
    CHECK(of(m, 1).match == SlaveMatch::Absent);
    CHECK(of(m, 2).match == SlaveMatch::Absent);
}

TEST_CASE_METHOD(Fixture, "a floating group is recognised at any free port", "[sequencer][hotconnect]") {
    // The probe plugged into J1's port C: it comes last in J1's port order.
    const auto report = bus_of({{&s(0), 0, {1, 2}}, {&s(3), 0, {1}}, {&s(5), 0, {}}, {&s(6), 103, {}}});
    const auto m = match(report);
    CHECK_FALSE(m.blocking());
    CHECK(m.groups[3] == GroupState::Present);
    CHECK(m.position[6] == std::uint16_t{3});
    CHECK(of(m, 6).previous_station == std::uint16_t{1001});
    CHECK(of(m, 6).previous_port == 'C');
}

TEST_CASE_METHOD(Fixture, "a floating group where a pinned group belongs takes its place", "[sequencer][hotconnect]") {
    // The probe (same type as the tool, alias 103) plugged into J2 port D, where the tool belongs.
    const auto report = bus_of({{&s(0), 0, {1}}, {&s(3), 0, {3, 1}}, {&s(6), 103, {}}, {&s(5), 0, {}}});
    const auto m = match(report);
    CHECK_FALSE(m.blocking());
    CHECK(m.groups[2] == GroupState::Absent);
    CHECK(m.groups[3] == GroupState::Present);
    CHECK(m.position[6] == std::uint16_t{2});
}

TEST_CASE_METHOD(Fixture, "a pinned group at the wrong port is refused", "[sequencer][hotconnect]") {
    // The tool (alias 102) plugged into J2 port C: it belongs at port D.
    const auto report = bus_of({{&s(0), 0, {1}}, {&s(3), 0, {1, 2}}, {&s(5), 0, {}}, {&s(4), 102, {}}});
    const auto m = match(report);
    CHECK(m.groups[2] == GroupState::Absent);
    const auto extra = unexpected(m);
    REQUIRE(extra.size() == 1);
    CHECK(extra[0]->position == 3);
    CHECK(extra[0]->previous_station == std::uint16_t{1004});
    CHECK(extra[0]->previous_port == 'C');
    CHECK_THAT(extra[0]->describe(), Catch::Contains("looks like 'tool', which belongs at station 1004 port D"));
    CHECK(m.blocking());  // at start-up an unexpected slave stops the bus
}

TEST_CASE_METHOD(Fixture, "a duplicate: the first one found is used, the second is unexpected", "[sequencer][hotconnect]") {
    // Two probes with alias 103: one at J2 port C, another at J1 port C (found later).
    const auto report = bus_of({{&s(0), 0, {1, 2}}, {&s(3), 0, {1, 2}}, {&s(5), 0, {}}, {&s(6), 103, {}},
                                {&s(6), 103, {}}});
    const auto m = match(report);
    CHECK(m.position[6] == std::uint16_t{3});
    const auto extra = unexpected(m);
    REQUIRE(extra.size() == 1);
    CHECK(extra[0]->position == 4);
    CHECK_THAT(extra[0]->note, Catch::Contains("duplicate of 'probe' (found at position 3)"));
    CHECK(extra[0]->previous_station == std::uint16_t{1001});
    CHECK(extra[0]->previous_port == 'C');
}

TEST_CASE_METHOD(Fixture, "an unknown slave at a free port, and one spliced into a cable", "[sequencer][hotconnect]") {
    SECTION("at a free port: unexpected with where it hangs, the rest as configured") {
        const auto report = bus_of({{&s(0), 0, {1, 2}}, {&s(3), 0, {1}}, {&s(5), 0, {}}, {nullptr, 0, {}, 0xBAD}});
        const auto m = match(report);
        CHECK(m.groups[0] == GroupState::Present);
        const auto extra = unexpected(m);
        REQUIRE(extra.size() == 1);
        CHECK(extra[0]->position == 3);
        CHECK(extra[0]->previous_station == std::uint16_t{1001});
        CHECK(extra[0]->previous_port == 'C');
        CHECK(extra[0]->previous_position == std::uint16_t{0});
        CHECK(extra[0]->note.empty());
    }
    SECTION("in the cable between J2 and the last slave") {
        const auto report = bus_of({{&s(0), 0, {1}}, {&s(3), 0, {1}}, {nullptr, 0, {1}, 0xBAD}, {&s(5), 0, {}}});
        const auto m = match(report);
        CHECK(m.position[5] == std::uint16_t{3});
        CHECK(of(m, 5).match == SlaveMatch::Match);
        CHECK(of(m, 5).previous_port == 'B');
        const auto extra = unexpected(m);
        REQUIRE(extra.size() == 1);
        CHECK(extra[0]->position == 2);
        CHECK(extra[0]->previous_station == std::uint16_t{1004});
    }
}

TEST_CASE_METHOD(Fixture, "a group with the wrong identification is refused, the bus goes on", "[sequencer][hotconnect]") {
    SECTION("station alias") {
        const auto report = bus_of({{&s(0), 0, {3, 1}}, {&s(1), 99, {1}}, {&s(2), 0, {}}, {&s(3), 0, {1}}, {&s(5), 0, {}}});
        const auto m = match(report);
        CHECK(m.groups[1] == GroupState::Refused);
        CHECK_FALSE(m.blocking());
        const auto& c = of(m, 1);
        CHECK(c.match == SlaveMatch::WrongIdentification);
        REQUIRE(c.identification);
        CHECK(c.identification->read == std::uint16_t{99});
        CHECK(c.identification->expected == 101);
        CHECK(c.previous_station == std::uint16_t{1001});
        CHECK(c.previous_port == 'D');
        CHECK(m.present()[1] == false);
        CHECK(m.present()[2] == false);
    }
    SECTION("IdentifyCmds") {
        probe.failing.insert(1);
        const auto report = bus_of({{&s(0), 0, {3, 1}}, {&s(1), 101, {1}}, {&s(2), 0, {}}, {&s(3), 0, {1}}, {&s(5), 0, {}}});
        const auto m = match(report);
        CHECK(m.groups[1] == GroupState::Refused);
        CHECK_THAT(of(m, 1).describe(), Catch::Contains("IdentifyCmds do not validate"));
    }
}

TEST_CASE_METHOD(Fixture, "a group whose member is missing is refused", "[sequencer][hotconnect]") {
    const auto report = bus_of({{&s(0), 0, {3, 1}}, {&s(1), 101, {}}, {&s(3), 0, {1}}, {&s(5), 0, {}}});
    const auto m = match(report);
    CHECK(m.groups[1] == GroupState::Refused);
    CHECK(of(m, 2).match == SlaveMatch::Missing);
    CHECK(of(m, 2).optional);
}

TEST_CASE_METHOD(Fixture, "a missing mandatory slave blocks, its groups count as absent", "[sequencer][hotconnect]") {
    const auto report = bus_of({{&s(0), 0, {}}});
    const auto m = match(report);
    CHECK(m.blocking());
    CHECK(of(m, 3).match == SlaveMatch::Missing);
    CHECK(of(m, 5).match == SlaveMatch::Missing);
    CHECK(of(m, 4).match == SlaveMatch::Absent);
    CHECK(of(m, 3).previous_station == std::uint16_t{1001});
    CHECK(of(m, 3).previous_port == 'B');
}

TEST_CASE_METHOD(Fixture, "behind a line break the slaves form a fragment of their own", "[sequencer][hotconnect]") {
    // The cable J1 B -> J2 is cut: J2 and the last slave are reached from the other side.
    const auto report = bus_of({{&s(0), 0, {}}, {&s(3), 0, {1}}, {&s(5), 0, {}}});
    const auto m = match(report);
    CHECK_FALSE(m.blocking());
    CHECK(m.position[3] == std::uint16_t{1});
    CHECK(m.position[5] == std::uint16_t{2});
}

TEST_CASE_METHOD(Fixture, "explicit device ID identification asks the probe", "[sequencer][hotconnect]") {
    eni.slaves[4].info.identification = eni::Identification{0x0134, 55, true};
    groups = eni::HotConnectGroups::of(eni);
    const auto report = bus_of({{&s(0), 0, {1}}, {&s(3), 0, {3, 1}}, {&s(4), 0, {}}, {&s(5), 0, {}}});
    probe.ids[2] = 54;
    CHECK(match(report).groups[2] == GroupState::Refused);
    probe.ids[2] = 55;
    CHECK(match(report).groups[2] == GroupState::Present);
}

}  // namespace
}  // namespace ecpair::test
