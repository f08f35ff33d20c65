#pragma once
// A BusAccess over an in-process simulated segment (tests, benchmarks, and
// anything that wants a master's view of ecsim without interfaces): each request becomes one
// frame with one datagram that enters the segment at MAIN; whatever side it
// leaves by, its datagram's data and WKC are the reply. A frame that dies
// on the way is a timeout. Simulated time moves on by a fixed step per
// frame. refuse() makes it answer like an INACTIVE master's queue.

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/sim/segment.hpp"

namespace ecpair::sim {

class SegmentBusAccess final : public bus::BusAccess {
public:
    static constexpr std::uint64_t kTimePerFrameNs = 100'000;

    explicit SegmentBusAccess(Segment& segment) : segment_(segment) {}

    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override;

    void refuse(std::optional<bus::BusErrc> reason);
    std::optional<bus::BusErrc> refusal() const override;
    std::uint64_t frames() const;
    // Runs `f` on the segment while no frame is travelling (faults, inspection).
    void with_segment(const std::function<void(Segment&)>& f);

private:
    Segment& segment_;
    mutable std::mutex mutex_;
    std::optional<bus::BusErrc> refusal_;
    std::uint64_t now_ns_ = 1'000'000'000;
    std::uint64_t frames_ = 0;
    std::uint8_t next_index_ = 0;
};

}  // namespace ecpair::sim
