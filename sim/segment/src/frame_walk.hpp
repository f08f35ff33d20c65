#pragma once
// The step machine that moves a frame through the segment (the three steps
// segment.cpp's opening comment describes), written once for its two users:
// Segment::carry drives it with the ESCs themselves, and FrameRoute drives it
// with the ESCs' pass digests to record the path frames take while no port
// changes. The policy answers what the wire asks:
//
//   bool cable_has_link(std::size_t cable)
//   bool port_open(std::size_t slave, int port)
//   void arrived(std::size_t slave, int port, std::uint64_t time_ns)
//   bool epu(std::size_t slave, std::uint64_t time_ns)   // false: the frame died there
//   std::uint64_t leaving_ns(std::size_t slave, int port, bool through_epu)  // time in the ESC
//   std::uint64_t cable_ns(std::size_t cable)                               // time on the cable
//
// The frame's time: it reaches the processing unit when it arrives at port
// 0 (or, port 0 closed, when it arrives at the port it came in by); it
// leaves an ESC by a port its forwarding or processing delay (EscDelays,
// by that port, processing when it passed the EPU since it arrived) after
// its arrival; the cable adds its delay.
// A walk can start anywhere (WalkState), so that a carry that followed a
// recorded route can go on step by step from where the route stopped holding.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "ecpair/sim/topology.hpp"

namespace ecpair::sim::detail {

enum class WalkStep : std::uint8_t { Transmit, Loopback, Epu };

struct WalkState {
    WalkStep step = WalkStep::Transmit;
    Endpoint leaving;       // Transmit: the end the frame leaves by
    std::size_t slave = 0;  // Loopback, Epu
    int port = 0;           // Loopback
    // The ports of `slave` from before its EPU pass, while the frame is still
    // inside that slave: the frame's own writes cannot change how it leaves.
    std::optional<std::array<bool, kPortCount>> open_before_epu;
    std::uint64_t time_ns = 0;  // of the last arrival (or the entry)
    bool through_epu = false;   // the frame passed `slave`'s EPU since it arrived there
    std::size_t steps = 0;      // steps taken so far (the bound counts from the frame's entry)
};

enum class WalkEnd : std::uint8_t { Left, LostNoLink, LostClosedPort, Destroyed, HopLimit };

struct WalkResult {
    WalkEnd end = WalkEnd::Left;
    Endpoint where;  // Left: the side; LostNoLink: the end without link; LostClosedPort: the closed port
    std::size_t slave = 0;  // Destroyed: whose EPU
};

template <class Policy>
WalkResult walk(const Topology& topology, WalkState& s, Policy& policy, std::size_t max_steps) {
    for (; s.steps < max_steps; ++s.steps) {
        switch (s.step) {
            case WalkStep::Transmit: {
                const auto cable = topology.cable_at(s.leaving);
                if (!cable || !policy.cable_has_link(*cable)) return {WalkEnd::LostNoLink, s.leaving};
                const Endpoint arriving = topology.peer(*cable, s.leaving);
                if (arriving.is_side()) return {WalkEnd::Left, arriving};
                if (!s.leaving.is_side()) s.time_ns += policy.leaving_ns(s.leaving.slave, s.leaving.port, s.through_epu);
                s.time_ns += policy.cable_ns(*cable);
                s.through_epu = false;
                const bool was_open = policy.port_open(arriving.slave, arriving.port);
                policy.arrived(arriving.slave, arriving.port, s.time_ns);
                if (!was_open) return {WalkEnd::LostClosedPort, arriving};
                s.slave = arriving.slave;
                s.open_before_epu.reset();
                if (arriving.port == 0) {
                    s.step = WalkStep::Epu;
                } else {
                    s.step = WalkStep::Loopback;
                    s.port = next_port(arriving.port);
                }
                break;
            }
            case WalkStep::Loopback:
                if (s.open_before_epu ? (*s.open_before_epu)[static_cast<std::size_t>(s.port)]
                                      : policy.port_open(s.slave, s.port)) {
                    s.step = WalkStep::Transmit;
                    s.leaving = Endpoint::of_port(s.slave, s.port);
                } else if (s.port == 0) {
                    s.step = WalkStep::Epu;
                } else {
                    s.port = next_port(s.port);
                }
                break;
            case WalkStep::Epu: {
                if (!s.open_before_epu) {
                    s.open_before_epu.emplace();
                    for (int p = 0; p < kPortCount; ++p) {
                        (*s.open_before_epu)[static_cast<std::size_t>(p)] = policy.port_open(s.slave, p);
                    }
                }
                if (!policy.epu(s.slave, s.time_ns)) return {WalkEnd::Destroyed, {}, s.slave};
                s.through_epu = true;
                s.step = WalkStep::Loopback;
                s.port = next_port(0);
                break;
            }
        }
    }
    return {WalkEnd::HopLimit, {}};
}

}  // namespace ecpair::sim::detail
