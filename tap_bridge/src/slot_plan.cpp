#include "ecpair/tap_bridge/slot_plan.hpp"

#include <algorithm>

namespace ecpair::tap_bridge {
namespace {

std::size_t datagrams_for(std::size_t bytes, std::size_t room) { return (bytes + room - 1) / room; }

bool due(std::uint32_t cycles_since) { return cycles_since + 1 >= kLightServeInterval; }

}  // namespace

SlotPlan plan_slots(const SlotDemand& d) {
    if (d.slots == 0) return {};
    const std::size_t data_room = std::max<std::size_t>(d.data_room, 1);
    const std::size_t poll_room = std::max<std::size_t>(d.poll_room, 1);
    const std::size_t own = datagrams_for(d.own_bytes, data_room);
    const std::size_t partner = datagrams_for(d.partner_bytes, poll_room);

    if (own == 0) return {0, std::clamp<std::size_t>(partner, 1, d.slots)};
    if (own + std::max<std::size_t>(partner, 1) <= d.slots) return {own, d.slots - own};

    // Congested: not everything goes out this cycle.
    const bool own_light = d.own_bytes < data_room / 2;
    const bool partner_light = d.partner_bytes < poll_room / 2;
    if (partner_light && !own_light) {
        const std::size_t polls = due(d.cycles_since_poll) ? 1 : 0;
        return {d.slots - polls, polls};
    }
    if (own_light && !partner_light) {
        const std::size_t data = due(d.cycles_since_data) ? 1 : 0;
        return {data, d.slots - data};
    }
    if (d.slots == 1) {
        // One frame a cycle: whoever waited longer.
        return d.cycles_since_data >= d.cycles_since_poll ? SlotPlan{1, 0} : SlotPlan{0, 1};
    }
    const std::size_t share = (d.slots * d.partner_bytes + (d.own_bytes + d.partner_bytes) / 2) /
                              (d.own_bytes + d.partner_bytes);
    const std::size_t polls = std::clamp<std::size_t>(share, 1, d.slots - 1);
    return {d.slots - polls, polls};
}

}  // namespace ecpair::tap_bridge
