// plan_slots(): how the ACTIVE spends its acyclic frames per cycle, every
// branch (slot_plan.hpp), and over many cycles the share a bulk transfer
// gets while the other side only acknowledges.

#include <catch2/catch.hpp>

#include "ecpair/tap_bridge/slot_plan.hpp"

using namespace ecpair::tap_bridge;

namespace {

constexpr std::size_t kRoom = 1462;

SlotDemand demand(std::size_t slots, std::size_t own, std::size_t partner, std::uint32_t since_data = 0,
                  std::uint32_t since_poll = 0) {
    SlotDemand d;
    d.slots = slots;
    d.own_bytes = own;
    d.partner_bytes = partner;
    d.data_room = kRoom;
    d.poll_room = kRoom;
    d.cycles_since_data = since_data;
    d.cycles_since_poll = since_poll;
    return d;
}

}  // namespace

TEST_CASE("no budget, no frames", "[tap_bridge]") { CHECK(plan_slots(demand(0, 5000, 5000)) == SlotPlan{0, 0}); }

TEST_CASE("idle: one poll a cycle, more when the partner reports a backlog", "[tap_bridge]") {
    CHECK(plan_slots(demand(4, 0, 0)) == SlotPlan{0, 1});
    CHECK(plan_slots(demand(4, 0, 2 * kRoom)) == SlotPlan{0, 2});
    CHECK(plan_slots(demand(4, 0, 100 * kRoom)) == SlotPlan{0, 4});
}

TEST_CASE("what fits goes out, the rest of the budget polls", "[tap_bridge]") {
    CHECK(plan_slots(demand(4, 100, 0)) == SlotPlan{1, 3});
    CHECK(plan_slots(demand(4, 2 * kRoom, kRoom)) == SlotPlan{2, 2});
    CHECK(plan_slots(demand(2, 100, 100)) == SlotPlan{1, 1});
}

TEST_CASE("congested: a light partner is polled every kLightServeInterval cycles", "[tap_bridge]") {
    CHECK(plan_slots(demand(4, 50 * kRoom, 0, 0, 0)) == SlotPlan{4, 0});
    CHECK(plan_slots(demand(4, 50 * kRoom, 100, 0, kLightServeInterval - 2)) == SlotPlan{4, 0});
    CHECK(plan_slots(demand(4, 50 * kRoom, 100, 0, kLightServeInterval - 1)) == SlotPlan{3, 1});
}

TEST_CASE("congested: our light data goes out every kLightServeInterval cycles", "[tap_bridge]") {
    CHECK(plan_slots(demand(2, 100, 50 * kRoom, 0, 0)) == SlotPlan{0, 2});
    CHECK(plan_slots(demand(2, 100, 50 * kRoom, kLightServeInterval - 1, 0)) == SlotPlan{1, 1});
}

TEST_CASE("congested both ways: shared by demand, one frame each at least", "[tap_bridge]") {
    CHECK(plan_slots(demand(4, 30 * kRoom, 10 * kRoom)) == SlotPlan{3, 1});
    CHECK(plan_slots(demand(4, 10 * kRoom, 10 * kRoom)) == SlotPlan{2, 2});
    CHECK(plan_slots(demand(4, 1000 * kRoom, kRoom)) == SlotPlan{3, 1});
    CHECK(plan_slots(demand(4, kRoom, 1000 * kRoom)) == SlotPlan{1, 3});
    // One frame a cycle: whoever waited longer.
    CHECK(plan_slots(demand(1, 10 * kRoom, 10 * kRoom, 3, 1)) == SlotPlan{1, 0});
    CHECK(plan_slots(demand(1, 10 * kRoom, 10 * kRoom, 1, 3)) == SlotPlan{0, 1});
}

TEST_CASE("a bulk transfer against acknowledgements keeps all but one frame in 32", "[tap_bridge]") {
    // Two frames a cycle, our queue always full, the partner always has a
    // few ACKs waiting (reported 0 after each answer: they fit one poll).
    std::uint32_t since_data = 0;
    std::uint32_t since_poll = 0;
    std::size_t data = 0;
    std::size_t polls = 0;
    for (int cycle = 0; cycle < 800; ++cycle) {
        const auto plan = plan_slots(demand(2, 40 * kRoom, 0, since_data, since_poll));
        data += plan.data;
        polls += plan.polls;
        since_data = plan.data > 0 ? 0 : since_data + 1;
        since_poll = plan.polls > 0 ? 0 : since_poll + 1;
    }
    CHECK(polls == 800 / kLightServeInterval);
    CHECK(data + polls == 1600);
}
