// Control request lines executed on a segment: responses and effects.

#include <catch2/catch.hpp>

#include "ecpair/sim/control_commands.hpp"
#include "segment_fixtures.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::test;

TEST_CASE("status reports sides, counters, breaks and every slave", "[control]") {
    Segment segment = line_segment(2);
    const std::string status = handle_control_line(segment, "status");
    CHECK_THAT(status, Catch::StartsWith("ok slaves=2 main=up red=up in=MAIN:0,RED:0 out=MAIN:0,RED:0 destroyed=0 "
                                         "lost_no_link=0 lost_closed_port=0 non_ecat_dropped=0 unprocessable=0 "
                                         "hop_limit=0 epus_passed=0 damaged_dropped=0 broken=none | 1 name=\"S1\" "
                                         "vendor=0x00000002"));
    CHECK_THAT(status, Catch::Contains("| 2 name=\"S2\""));
    CHECK_THAT(status,
               Catch::Contains("addr=0x0000 alias=0x0000 al=INIT code=0x0000 powered=yes unknown=no ports=0:up/open,1:up/open"));
    CHECK(status.find('\n') == std::string::npos);
}

TEST_CASE("fault requests change the segment and say so", "[control]") {
    Segment segment = line_segment(3);
    CHECK(handle_control_line(segment, "break 2") == "ok link after slave 2 broken");
    CHECK_FALSE(segment.link_after_intact(2));
    CHECK_THAT(handle_control_line(segment, "status"), Catch::Contains("broken=2 "));
    CHECK(handle_control_line(segment, "repair 2") == "ok link after slave 2 repaired");
    CHECK(segment.link_after_intact(2));

    CHECK(handle_control_line(segment, "power-off 1") == "ok slave 1 powered off");
    CHECK_FALSE(segment.slave(1).powered());
    CHECK_THAT(handle_control_line(segment, "status"),
               Catch::Contains("| 1 name=\"S1\"") && Catch::Contains("powered=no unknown=no ports=0:down/"));
    CHECK(handle_control_line(segment, "power-on 1") == "ok slave 1 powered on");
    CHECK(segment.slave(1).powered());

    CHECK(handle_control_line(segment, "insert-unknown 4") == "ok unknown slave inserted as slave 4");
    CHECK_THAT(handle_control_line(segment, "status"),
               Catch::Contains("| 4 name=\"unknown slave\" vendor=0x0badc0de") && Catch::Contains("unknown=yes"));
    CHECK(handle_control_line(segment, "remove-unknown 4") == "ok unknown slave 4 removed");
    CHECK(segment.slave_count() == 3);

    CHECK(handle_control_line(segment, "set-alias 2 0x1234") ==
          "ok slave 2 EEPROM alias 0x1234 (taken over at its next EEPROM load)");
    CHECK(handle_control_line(segment, "set-id 3 7") == "ok slave 3 ID selector 0x0007");
}

TEST_CASE("refused requests answer error: with the reason", "[control]") {
    Segment segment = line_segment(3);
    CHECK(handle_control_line(segment, "power-off 9") == "error: position 9 is out of range 1..3");
    CHECK(handle_control_line(segment, "break 4") == "error: link 4 is out of range 0..3");
    CHECK(handle_control_line(segment, "remove-unknown 1") ==
          "error: slave 1 is 'S1' from the ENI; only slaves added by insert-unknown, plug-unknown or plug-duplicate can be removed");
    CHECK(handle_control_line(segment, "bogus") == "error: unknown command 'bogus' (try 'help')");
    CHECK_THAT(handle_control_line(segment, "help"), Catch::StartsWith("ok commands: status; help; power-off K;"));
}

TEST_CASE("the mailbox commands need a slave whose mailbox offers the protocol", "[control]") {
    Segment segment = line_segment(2);  // slaves without a mailbox
    CHECK(handle_control_line(segment, "emergency 1 0x8130") ==
          "error: slave 1 sends no emergency: its mailbox offers no CoE");
    CHECK(handle_control_line(segment, "foe-password 2 7") == "error: slave 2 offers no FoE");
    CHECK(handle_control_line(segment, "foe-busy 2 1") == "error: slave 2 offers no FoE");
    CHECK(handle_control_line(segment, "emergency 5 1") == "error: position 5 is out of range 1..2");
}
