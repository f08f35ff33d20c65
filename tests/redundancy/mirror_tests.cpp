// Mirror on its own: the INACTIVE's image of a cycle is the CMF's inputs and
// the outputs of that cycle's output frames, and a link that missed one of
// those frames never lends an older cycle's outputs to the record.

#include <catch2/catch.hpp>

#include <array>

#include "cmf_test_support.hpp"
#include "ecpair/common/crc32.hpp"
#include "mirror.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;
using ecpair::test::TestContent;
using master::LinkRole;

namespace {

constexpr std::uint32_t kOutputAddress = 0x00010000;
constexpr std::uint16_t kOutputLength = 4;

// One LWR of 4 output bytes, sent in SAFEOP and OP.
master::CyclicPlan output_plan() {
    master::PlannedDatagram lwr;
    lwr.command = wire::Command::Lwr;
    lwr.address = kOutputAddress;
    lwr.length = kOutputLength;
    lwr.output_offset = 0;
    lwr.states.add(eni::SlaveState::Safeop);
    lwr.states.add(eni::SlaveState::Op);
    master::CyclicPlan plan;
    plan.output_image_size = kOutputLength;
    plan.frames.push_back(master::PlannedFrame{{lwr}});
    return plan;
}

// The ACTIVE's output frame of a cycle: the LWR with `outputs`.
std::vector<std::uint8_t> output_frame(const std::array<std::uint8_t, kOutputLength>& outputs) {
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    test::CapturingSender sender;
    wire::FrameBuilder builder(buffer, sender.ethernet());
    builder.append(wire::DatagramHeader{wire::Command::Lwr, 0, kOutputAddress}, outputs);
    const auto frame = builder.finish();
    return {frame.begin(), frame.end()};
}

std::array<std::uint8_t, kOutputLength> outputs_of(std::uint64_t cycle) {
    const auto c = static_cast<std::uint8_t>(cycle);
    return {c, static_cast<std::uint8_t>(c + 1), static_cast<std::uint8_t>(c * 3), 0x5A};
}

std::vector<std::uint8_t> output_image_of(std::uint64_t cycle) {
    const auto outputs = outputs_of(cycle);
    return {outputs.begin(), outputs.end()};
}

struct MirrorBench {
    CmfLayout layout = test::small_layout();
    master::EventQueue events;
    ImageHistory history{64};
    Mirror mirror{test::plan_of(layout), output_plan(), layout.shadow_inputs_size, kOutputLength, events, history};

    void output(LinkRole link, std::uint64_t cycle) { mirror.on_first_pass(link, output_frame(outputs_of(cycle))); }
    void cmf(LinkRole link, std::uint64_t cycle, eni::SlaveState state = eni::SlaveState::Op) {
        TestContent content(layout, cycle);
        content.content.master_state = state;
        content.content.flags = CmfFlags{};
        for (const auto& frame : test::write_cmf(layout, content.content)) mirror.on_first_pass(link, frame.bytes);
    }
    // The record the mirror should make of `cycle` (the CMF's inputs, the cycle's outputs).
    ImageRecord expected(std::uint64_t cycle, eni::SlaveState state = eni::SlaveState::Op) const {
        const TestContent content(layout, cycle);
        return ImageRecord{cycle, crc32(content.shadow_inputs), crc32(outputs_of(cycle)), state, true};
    }
};

}  // namespace

TEST_CASE("the mirror records a cycle from its output frame and its CMF on one link", "[redundancy][mirror]") {
    MirrorBench bench;
    bench.output(LinkRole::Main, 5);
    bench.cmf(LinkRole::Main, 5);
    bench.output(LinkRole::Red, 5);
    bench.cmf(LinkRole::Red, 5);  // the second copy: recorded once
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(5)});
    MirroredCycle taken;
    taken.outputs.resize(kOutputLength);
    REQUIRE(bench.mirror.take_newer(taken));
    CHECK(taken.cycle == 5);
    CHECK(taken.complete);
    CHECK(taken.outputs_known);
    CHECK(taken.outputs == output_image_of(5));
}

TEST_CASE("an output frame lost on the first copy's link: the outputs come from the other copy",
          "[redundancy][mirror]") {
    MirrorBench bench;
    bench.output(LinkRole::Main, 5);
    bench.cmf(LinkRole::Main, 5);
    // Cycle 6: MAIN's output frame is lost, its CMF arrives first. MAIN's
    // outputs are cycle 5's: the mirror must not call them cycle 6's.
    bench.cmf(LinkRole::Main, 6);
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(5)});
    MirroredCycle taken;
    taken.outputs.resize(kOutputLength);
    REQUIRE(bench.mirror.take_newer(taken));
    CHECK(taken.cycle == 6);
    CHECK_FALSE(taken.outputs_known);
    CHECK_FALSE(bench.mirror.take_newer(taken));  // nothing new yet
    // RED's copy brought the output frame: now cycle 6 is known and recorded.
    bench.output(LinkRole::Red, 6);
    bench.cmf(LinkRole::Red, 6);
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(5), bench.expected(6)});
    REQUIRE(bench.mirror.take_newer(taken));  // the same cycle, now with its outputs
    CHECK(taken.cycle == 6);
    CHECK(taken.outputs_known);
    CHECK(taken.outputs == output_image_of(6));
}

TEST_CASE("a cycle whose output frame neither link saw is not recorded", "[redundancy][mirror]") {
    MirrorBench bench;
    bench.output(LinkRole::Main, 7);
    bench.cmf(LinkRole::Main, 7);
    bench.cmf(LinkRole::Main, 8);
    bench.cmf(LinkRole::Red, 8);
    bench.output(LinkRole::Main, 9);
    bench.cmf(LinkRole::Main, 9);
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(7), bench.expected(9)});
}

TEST_CASE("an output frame seen before mirroring restarts belongs to no later cycle", "[redundancy][mirror]") {
    MirrorBench bench;
    bench.output(LinkRole::Main, 3);
    bench.cmf(LinkRole::Main, 3);
    // Cycle 4's output frame arrives, then this master leaves the mirror
    // (it took over) and comes back: the first CMF it completes is cycle
    // 40's, whose output frame passed while it was not mirroring.
    bench.output(LinkRole::Main, 4);
    bench.mirror.reset();
    bench.cmf(LinkRole::Main, 40);
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(3)});
    bench.output(LinkRole::Main, 41);
    bench.cmf(LinkRole::Main, 41);
    CHECK(bench.history.snapshot() == std::vector<ImageRecord>{bench.expected(3), bench.expected(41)});
}

TEST_CASE("in a state without output datagrams the CMF alone makes the record", "[redundancy][mirror]") {
    MirrorBench bench;
    bench.cmf(LinkRole::Red, 2, eni::SlaveState::Preop);
    const TestContent content(bench.layout, 2);
    // No output frame in PREOP: the outputs recorded are the image as it is (zero).
    CHECK(bench.history.snapshot() ==
          std::vector<ImageRecord>{{2, crc32(content.shadow_inputs), crc32(std::array<std::uint8_t, kOutputLength>{}),
                                    eni::SlaveState::Preop, true}});
}
