// The Hot-Connect faults of a segment built from a generated ENI with
// groups at junction ports (hot-connect.md §8 needs them all): a group's
// power, a floating group unplugged at first and plugged where an operator
// wants it, an unknown slave and a duplicate at free ports, a slave that
// refuses a state, the ETG.1020 selector, and the control requests for each.

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/sim/control_commands.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "segment_fixtures.hpp"

namespace ecpair::test {
namespace {

sim::Segment segment_of(const sim::GeneratedEniOptions& options) {
    const auto eni = eni::load_eni_string(sim::generate_eni(options), "generated.xml");
    REQUIRE(eni);
    auto segment = sim::Segment::from_eni(**eni);
    REQUIRE(segment);
    return std::move(segment).value();
}

sim::GeneratedEniOptions two_groups(bool floating = false) {
    sim::GeneratedEniOptions o;
    o.slaves = 3;
    o.groups = 2;
    o.group_slaves = 2;
    o.input_bytes = 4;
    o.output_bytes = 4;
    o.floating = floating;
    return o;
}

// How many slaves a BRD from MAIN counts, and where the frame came out.
std::uint16_t slaves_answering(sim::Segment& segment) {
    TestFrame frame = ethercat_frame({DatagramSpec{wire::Command::Brd, 0x01300000, {0, 0}}});
    const auto exit = carry(segment, sim::Side::Main, frame);
    REQUIRE(exit);
    return wkc_of(frame);
}

TEST_CASE("groups at junction ports: all plugged in, one powered off and on again", "[segment][hotconnect]") {
    auto segment = segment_of(two_groups());
    REQUIRE(segment.slave_count() == 7);
    CHECK(segment.group_count() == 2);
    CHECK(segment.group_of(2) == 1);  // file order: junction, group 1 (2 slaves), junction, group 2, end
    CHECK(segment.group_of(5) == 2);
    CHECK(slaves_answering(segment) == 7);

    REQUIRE(segment.set_group_power(1, false));
    CHECK_FALSE(segment.slave(2).powered());
    CHECK_FALSE(segment.slave(3).powered());
    CHECK(slaves_answering(segment) == 5);
    REQUIRE(segment.set_group_power(1, true));
    CHECK(slaves_answering(segment) == 7);
    CHECK(segment.slave(2).station_address() == 0);  // a fresh power-on

    CHECK(handle_control_line(segment, "group-off 2") == "ok group 2 powered off");
    CHECK(slaves_answering(segment) == 5);
    CHECK(handle_control_line(segment, "group-on 2") == "ok group 2 powered on");
    CHECK(handle_control_line(segment, "group-off 3") == "error: group 3 is out of range 1..2");
    CHECK_THAT(sim::format_status(segment), Catch::Contains("| 2 name=\"Group 1 IO 1\"") && Catch::Contains("group=1"));
}

TEST_CASE("a floating group starts unplugged and goes where it is plugged", "[segment][hotconnect]") {
    auto segment = segment_of(two_groups(/*floating=*/true));
    REQUIRE(segment.slave_count() == 7);  // the line (3), then the groups
    CHECK(slaves_answering(segment) == 3);
    CHECK(handle_control_line(segment, "plug-group 1 2 D") == "ok group 1 plugged into slave 2 port D");
    CHECK(slaves_answering(segment) == 5);
    // Moving it: unplugged from slave 2, plugged into slave 1.
    REQUIRE(segment.plug_group(1, 1, 3));
    CHECK(slaves_answering(segment) == 5);
    CHECK(handle_control_line(segment, "plug-group 2 1 D") == "error: slave 1 port 3 already has a cable");
    CHECK(handle_control_line(segment, "unplug-group 1") == "ok group 1 unplugged");
    CHECK(slaves_answering(segment) == 3);
    CHECK(handle_control_line(segment, "unplug-group 1") == "error: slave 4 is not plugged in");
}

TEST_CASE("an unknown slave and a duplicate plugged into free ports, and taken out", "[segment][hotconnect]") {
    auto segment = segment_of(two_groups());
    // Port C of a junction comes after port B in a frame's path: in a ring the
    // frame from MAIN leaves at RED before it gets there. Without the ring's
    // return cable (a single master) the line's end turns it back, and it does.
    segment.set_side_link(sim::Side::Red, false);
    CHECK(handle_control_line(segment, "plug-unknown 1 C") == "ok unknown slave plugged into slave 1 port C as slave 8");
    CHECK(segment.is_unknown(8));
    CHECK(segment.slave(8).description().vendor_id == sim::kUnknownSlaveVendorId);
    CHECK(slaves_answering(segment) == 8);
    CHECK(handle_control_line(segment, "plug-duplicate 2 4 C") ==
          "ok a duplicate of slave 2 plugged into slave 4 port C as slave 9");
    CHECK(segment.slave(9).description().product_code == segment.slave(2).description().product_code);
    CHECK(segment.slave(9).description().alias == segment.slave(2).description().alias);
    CHECK(slaves_answering(segment) == 9);
    CHECK(handle_control_line(segment, "remove-unknown 9") == "ok unknown slave 9 removed");
    CHECK(handle_control_line(segment, "remove-unknown 8") == "ok unknown slave 8 removed");
    CHECK(slaves_answering(segment) == 7);
    CHECK(handle_control_line(segment, "plug-unknown 1 B") == "error: slave 1 port 1 already has a cable");
}

TEST_CASE("refuse-state and set-selector reach the slave", "[segment][hotconnect]") {
    auto segment = segment_of(two_groups());
    CHECK(handle_control_line(segment, "refuse-state 2 SAFEOP") == "ok slave 2 refuses SAFEOP and above");
    CHECK(handle_control_line(segment, "refuse-state 2 none") == "ok slave 2 refuses no state");
    CHECK(handle_control_line(segment, "refuse-state 2 BOOT") ==
          "error: refuse-state: STATE must be PREOP, SAFEOP, OP or none, got 'BOOT'");
    CHECK(handle_control_line(segment, "set-selector 2 17") ==
          "ok slave 2 ETG.1020 ID selector 17 (read at its next power-on)");
    REQUIRE(segment.power_off(2));
    REQUIRE(segment.power_on(2));
    CHECK(segment.slave(2).station_alias() == 17);
}

}  // namespace
}  // namespace ecpair::test
