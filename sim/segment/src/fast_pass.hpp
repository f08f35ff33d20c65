#pragma once
// What the segment keeps for its fast pass (segment_carry.cpp): every ESC's
// pass digest, the recorded route of each side, and for the frame being
// carried which ESCs process it.

#include <array>
#include <cstdint>
#include <vector>

#include "ecpair/sim/esc.hpp"
#include "ecpair/sim/topology.hpp"
#include "frame_addressing.hpp"
#include "frame_route.hpp"

namespace ecpair::sim::detail {

struct FastPass {
    std::vector<PassDigest> digests;  // per slave
    std::size_t not_passable = 0;     // digests that are not passable
    // Per slave: the sequence number of the last frame the ESC processed on the fast pass.
    std::vector<std::uint64_t> called;
    // The route steps of the frame being carried that call an ESC, in route order.
    std::vector<std::uint32_t> calls;
    std::array<FrameRoute, kSideCount> routes;
    std::array<bool, kSideCount> route_valid{};
    FrameAddressing addressing;

    void forget_routes() { route_valid = {}; }
};

}  // namespace ecpair::sim::detail
