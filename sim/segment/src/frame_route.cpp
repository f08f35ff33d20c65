#include "frame_route.hpp"

namespace ecpair::sim::detail {
namespace {

constexpr std::uint32_t kNotOnRoute = 0xFFFFFFFF;

// The step machine's questions answered from the digests, every arrival and
// EPU pass written down.
struct RecordingPolicy {
    std::span<const PassDigest> digests;
    const std::function<bool(std::size_t)>& link;
    std::vector<RouteStep>& steps;
    const WalkState& state;
    std::uint64_t cable_delay_ns;
    std::uint32_t epus = 0;

    bool cable_has_link(std::size_t cable) const { return link(cable); }
    bool port_open(std::size_t slave, int port) const { return (digests[slave].open_ports & (1U << port)) != 0; }
    std::uint64_t leaving_ns(std::size_t slave, int port, bool through_epu) const {
        return digests[slave].delays.leaving(port, through_epu);
    }
    std::uint64_t cable_ns(std::size_t /*cable*/) const { return cable_delay_ns; }
    void arrived(std::size_t slave, int port, std::uint64_t time_ns) {
        steps.push_back(RouteStep{RouteStep::Kind::Arrival, port, slave, epus, time_ns, state.steps + 1});
    }
    bool epu(std::size_t slave, std::uint64_t time_ns) {
        steps.push_back(RouteStep{RouteStep::Kind::Epu, 0, slave, epus++, time_ns, state.steps + 1});
        return true;  // only an ESC that is not passable destroys frames, and the carry asks it
    }
};

}  // namespace

bool FrameRoute::record(const Topology& topology, std::span<const PassDigest> digests, Side entry,
                        const std::function<bool(std::size_t cable)>& cable_has_link, std::uint64_t cable_ns,
                        std::size_t max_steps) {
    steps_.clear();
    slaves_.clear();
    WalkState state;
    state.leaving = Endpoint::of_side(entry);
    RecordingPolicy policy{digests, cable_has_link, steps_, state, cable_ns};
    end_ = walk(topology, state, policy, max_steps);
    epu_count_ = policy.epus;
    last_epu_after_ns_ = 0;
    index_of_.assign(digests.size(), kNotOnRoute);
    for (std::uint32_t i = 0; i < steps_.size(); ++i) {
        const RouteStep& step = steps_[i];
        std::uint32_t& index = index_of_[step.slave];
        if (index == kNotOnRoute) {
            index = static_cast<std::uint32_t>(slaves_.size());
            slaves_.push_back(RouteSlave{step.slave});
        }
        RouteSlave& slave = slaves_[index];
        // Each port of a slave is reached at most once and its EPU once, so
        // the steps fit; a route that breaks that bound is not used.
        if (slave.step_count == slave.steps.size()) return false;
        slave.steps[slave.step_count++] = i;
        if (step.kind == RouteStep::Kind::Epu) {
            slave.epu_pass = step.epus_before;
            slave.epu_step = i;
            last_epu_after_ns_ = step.after_ns;
        }
    }
    return end_.end != WalkEnd::HopLimit;
}

}  // namespace ecpair::sim::detail
