#pragma once
// Segments for the tests: a line of identical 2-port slaves described by
// hand, and a shortcut to carry a TestFrame through a segment.

#include <catch2/catch.hpp>

#include <optional>
#include <string>
#include <vector>

#include "ecpair/sim/segment.hpp"
#include "test_frames.hpp"

namespace ecpair::test {

inline sim::EscDescription test_slave(const std::string& name, const std::string& physics = "YY") {
    sim::EscDescription description;
    description.name = name;
    description.vendor_id = 0x00000002;
    description.product_code = 0x07D83052;
    description.revision_no = 0x00100000;
    description.physics = physics;
    return description;
}

// Slaves "S1".."Sn" with PhysAddr 1001.., wired as a line (no PreviousPort).
inline std::vector<sim::SlaveSpec> line_specs(std::size_t n) {
    std::vector<sim::SlaveSpec> specs;
    for (std::size_t i = 1; i <= n; ++i) {
        specs.push_back(
            sim::SlaveSpec{test_slave("S" + std::to_string(i)), static_cast<std::uint16_t>(1000 + i), std::nullopt, 0});
    }
    return specs;
}

inline sim::Segment line_segment(std::size_t n) {
    auto segment = sim::Segment::from_specs(line_specs(n));
    REQUIRE(segment);
    return std::move(segment).value();
}

inline std::optional<sim::Side> carry(sim::Segment& segment, sim::Side entry, TestFrame& frame,
                                      std::uint64_t now_ns = 1'000'000) {
    return segment.carry(entry, frame.buffer, frame.size, now_ns);
}

// Carries a one-datagram frame and returns it as it came out (nullopt: it died).
inline std::optional<TestFrame> send(sim::Segment& segment, sim::Side entry, sim::Side expected_exit,
                                     wire::Command command, std::uint32_t address, std::vector<std::uint8_t> data) {
    TestFrame frame = ethercat_frame({DatagramSpec{command, address, std::move(data)}});
    const auto exit = carry(segment, entry, frame);
    if (!exit) return std::nullopt;
    CHECK(*exit == expected_exit);
    return frame;
}

}  // namespace ecpair::test
