// The tie-break rule: more slaves reached, then the older epoch, then the lower MAC.

#include <catch2/catch.hpp>

#include "ecpair/arbitration/contender.hpp"

using namespace ecpair::arbitration;

TEST_CASE("the master that reaches more slaves is preferred, whatever its epoch or MAC", "[arbitration]") {
    const Contender big_half{9, 20, 0x0200000000FF};
    const Contender small_half{2, 13, 0x020000000001};
    CHECK(compare(big_half, small_half).preference == Preference::Ours);
    CHECK(compare(small_half, big_half).preference == Preference::Theirs);
    CHECK(compare(big_half, small_half).decided_by == DecidedBy::SlavesReached);
    CHECK(compare_reach(big_half, small_half).preference == Preference::Ours);
}

TEST_CASE("with the same reach the older epoch wins, then the lower MAC", "[arbitration]") {
    const Contender older{4, 33, 0x0200000000FF};
    const Contender newer{5, 33, 0x020000000001};
    CHECK(compare(older, newer).preference == Preference::Ours);
    CHECK(compare(older, newer).decided_by == DecidedBy::Epoch);
    CHECK(compare_reach(older, newer).preference == Preference::Undecided);

    const Contender low_mac{5, 33, 0x020000000001};
    const Contender high_mac{5, 33, 0x020000000002};
    CHECK(compare(high_mac, low_mac).preference == Preference::Theirs);
    CHECK(compare(high_mac, low_mac).decided_by == DecidedBy::Mac);
    CHECK(compare(low_mac, low_mac).preference == Preference::Undecided);
}

TEST_CASE("a member is named by its MAC", "[arbitration]") {
    CHECK(member_name(0x0200000000A1) == "02:00:00:00:00:a1");
}
