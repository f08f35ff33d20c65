// Two members' image histories compared: only a cycle one member recorded as
// the ACTIVE and the other as its mirror is compared; cycles both recorded
// as the ACTIVE are named apart; before SAFEOP nothing counts.

#include <catch2/catch.hpp>

#include "ecpair/control/image_history_comparison.hpp"

using namespace ecpair::control;

namespace {

void add(ImageHistoryReply& history, std::uint64_t cycle, bool mirrored, std::uint32_t inputs = 0,
         std::uint32_t outputs = 0, const char* state = "OP") {
    auto* e = history.add_entries();
    e->set_cycle(cycle);
    e->set_inputs_crc(inputs == 0 ? static_cast<std::uint32_t>(cycle * 3) : inputs);
    e->set_outputs_crc(outputs == 0 ? static_cast<std::uint32_t>(cycle * 5) : outputs);
    e->set_master_state(state);
    e->set_mirrored(mirrored);
}

}  // namespace

TEST_CASE("a mirror equal to the ACTIVE's image in every common cycle is mirrored", "[control][history]") {
    ImageHistoryReply active;
    ImageHistoryReply mirror;
    for (std::uint64_t c = 10; c < 20; ++c) add(active, c, false);
    for (std::uint64_t c = 14; c < 25; ++c) add(mirror, c, true);  // joined late, ran longer
    const auto r = compare_image_histories(active, mirror);
    CHECK(r.common_cycles == 6);
    CHECK(r.differ.empty());
    CHECK(r.both_active.empty());
    CHECK(r.mirrored());
    // Either order: the side that recorded as the ACTIVE is the reference.
    CHECK(compare_image_histories(mirror, active).common_cycles == 6);
}

TEST_CASE("the cycles that differ say which half differs", "[control][history]") {
    ImageHistoryReply active;
    ImageHistoryReply mirror;
    for (std::uint64_t c = 1; c <= 8; ++c) add(active, c, false);
    for (std::uint64_t c = 1; c <= 8; ++c) {
        add(mirror, c, true, c == 3 ? 0xBAD : 0, c == 6 ? 0xBAD : 0, c == 7 ? "SAFEOP" : "OP");
    }
    const auto r = compare_image_histories(active, mirror);
    CHECK(r.common_cycles == 8);
    REQUIRE(r.differ.size() == 3);
    CHECK(r.differ[0].cycle == 3);
    CHECK(r.differ[0].inputs_differ);
    CHECK_FALSE(r.differ[0].outputs_differ);
    CHECK(r.differ[1].cycle == 6);
    CHECK(r.differ[1].outputs_differ);
    CHECK(r.differ[2].state_differs);
    CHECK_FALSE(r.mirrored());
    CHECK(r.describe() == "8 cycles compared (ACTIVE's image against the mirror), 3 differ; cycle 3: inputs; "
                          "cycle 6: outputs; cycle 7: master state");
    // Only the newest two common cycles.
    const auto newest = compare_image_histories(active, mirror, 2);
    CHECK(newest.common_cycles == 2);
    CHECK(newest.differ.size() == 1);
}

TEST_CASE("a cycle both members recorded as the ACTIVE is named, not compared", "[control][history]") {
    ImageHistoryReply m1;
    ImageHistoryReply m2;
    for (std::uint64_t c = 1; c <= 5; ++c) add(m1, c, false);
    for (std::uint64_t c = 1; c <= 5; ++c) add(m2, c, c != 4, c == 4 ? 0xBAD : 0);  // m2 sent in cycle 4
    const auto r = compare_image_histories(m1, m2);
    CHECK(r.common_cycles == 4);
    CHECK(r.differ.empty());
    CHECK(r.both_active == std::vector<std::uint64_t>{4});
    CHECK_FALSE(r.mirrored());
    CHECK(r.describe() == "4 cycles compared (ACTIVE's image against the mirror), 0 differ; 1 cycle(s) recorded as "
                          "the ACTIVE by both members (both sent), the first 4");
}

TEST_CASE("cycles before SAFEOP and cycles two mirrors recorded are not compared", "[control][history]") {
    ImageHistoryReply a;
    ImageHistoryReply b;
    add(a, 1, false, 0, 0, "PREOP");
    add(b, 1, true, 0xBAD, 0, "PREOP");
    add(a, 2, true);
    add(b, 2, true, 0xBAD);
    const auto r = compare_image_histories(a, b);
    CHECK(r.common_cycles == 0);
    CHECK(r.differ.empty());
    CHECK_FALSE(r.mirrored());  // nothing compared proves nothing
}
