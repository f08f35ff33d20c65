#pragma once
// The path a frame entering at one side takes through the segment while no
// port, link or power changes: the arrivals at slave ports and the EPU
// passes, in order, each with its time after entry, and how the path ends.
// Recorded by walking the step machine (frame_walk.hpp) over the ESCs' pass
// digests; the segment records it again after anything that may change a
// path (segment_carry.cpp says when).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "ecpair/sim/esc.hpp"
#include "frame_walk.hpp"

namespace ecpair::sim::detail {

struct RouteStep {
    enum class Kind : std::uint8_t { Arrival, Epu };

    Kind kind = Kind::Arrival;
    int port = 0;  // Arrival
    std::size_t slave = 0;
    std::uint32_t epus_before = 0;  // EPUs the frame passed before this step
    std::uint64_t after_ns = 0;     // time since the frame entered
    std::size_t walked = 0;         // the step machine's steps up to and including this one
};

// A slave on the route: where its steps are, and how many EPUs the frame
// passes before this slave's (what APxx counts).
struct RouteSlave {
    static constexpr std::uint32_t kNoEpu = 0xFFFFFFFF;
    std::size_t slave = 0;
    std::uint32_t epu_pass = kNoEpu;  // kNoEpu: the route passes no EPU of this slave
    std::uint32_t epu_step = 0;       // the index of that EPU step
    std::uint8_t step_count = 0;
    std::array<std::uint32_t, kPortCount + 1> steps{};  // indexes into steps(), in order
};

class FrameRoute {
public:
    // Records the route from `entry`. False when the walk ran into the step
    // bound: there is no route then, and frames take the step machine.
    bool record(const Topology& topology, std::span<const PassDigest> digests, Side entry,
                const std::function<bool(std::size_t cable)>& cable_has_link, std::uint64_t cable_ns,
                std::size_t max_steps);
    // Room for a segment of `slaves`, so that recording allocates nothing.
    void reserve(std::size_t slaves) {
        steps_.reserve((kPortCount + 1) * (slaves + 1));
        slaves_.reserve(slaves);
        index_of_.reserve(slaves);
    }

    std::span<const RouteStep> steps() const { return steps_; }
    // The slaves the route reaches, in the order it first reaches them.
    std::span<const RouteSlave> slaves() const { return slaves_; }
    const WalkResult& end() const { return end_; }
    std::uint32_t epu_count() const { return epu_count_; }
    // The latest time after entry at which the route reaches an EPU.
    std::uint64_t last_epu_after_ns() const { return last_epu_after_ns_; }

private:
    std::vector<RouteStep> steps_;
    std::vector<RouteSlave> slaves_;
    std::vector<std::uint32_t> index_of_;  // per slave: its index in slaves_, while recording
    WalkResult end_;
    std::uint32_t epu_count_ = 0;
    std::uint64_t last_epu_after_ns_ = 0;
};

}  // namespace ecpair::sim::detail
