#pragma once
// How the ACTIVE spends its acyclic frame budget of a cycle
// (max_acyc_frames_per_cycle) between its own frames (DATA) and polls that
// the INACTIVE fills (POLL). A pure function of the demand on both sides, so
// that every branch is tested without a clock:
//
//   idle      nothing of ours queued: poll, as often as the partner's
//             reported backlog needs, at least once per cycle (a frame the
//             partner queues now leaves at the next cycle)
//   fits      our data and the partner's backlog fit the budget: send all of
//             ours, spend the rest on polls
//   congested a side with little demand (under half a datagram: ACKs) is
//             served once every kLightServeInterval cycles, so that a bulk
//             transfer the other way keeps nearly every frame; two sides with
//             bulk demand share the frames in proportion, one each at least.

#include <cstddef>
#include <cstdint>

namespace ecpair::tap_bridge {

inline constexpr std::uint32_t kLightServeInterval = 16;

struct SlotDemand {
    std::size_t slots = 0;            // frames the budget allows this cycle
    std::size_t own_bytes = 0;        // queued here, with the 2-byte length of each frame
    std::size_t partner_bytes = 0;    // the partner's backlog as its last answer reported it
    std::size_t data_room = 1;        // payload bytes of one DATA datagram
    std::size_t poll_room = 1;        // payload bytes of one POLL
    std::uint32_t cycles_since_data = 0;  // cycles since our data last went out (0: last cycle)
    std::uint32_t cycles_since_poll = 0;  // cycles since a poll last went out
};

struct SlotPlan {
    std::size_t data = 0;
    std::size_t polls = 0;
    friend bool operator==(const SlotPlan&, const SlotPlan&) = default;
};

SlotPlan plan_slots(const SlotDemand& demand);

}  // namespace ecpair::tap_bridge
