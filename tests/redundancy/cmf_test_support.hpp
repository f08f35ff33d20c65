#pragma once
// Shared by the CMF tests, the fuzz target and the corpus generator: a
// FrameSender that keeps what it is given, the layouts the tests use, and
// content filled with recognisable bytes.

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "ecpair/master/cycle_extension.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::test {

struct SentCmfFrame {
    std::uint16_t index = 0;
    std::vector<std::uint8_t> bytes;
};

// Keeps a copy of every frame sent; the Ethernet header is what a master's
// sender gives (broadcast destination, source filled in per copy).
class CapturingSender final : public master::FrameSender {
public:
    Bytes buffer() override { return buffer_; }
    wire::EthernetHeader ethernet() const override {
        wire::EthernetHeader h;
        h.destination = wire::MacAddress::broadcast();
        h.source = wire::MacAddress{{0x00, 0x00, 0x00, 0x11, 0x22, 0x33}};
        return h;
    }
    void send(std::uint16_t index, Bytes frame) override { frames.push_back({index, {frame.begin(), frame.end()}}); }

    std::vector<SentCmfFrame> frames;

private:
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer_{};
};

inline redundancy::PairParameters test_parameters(std::uint32_t pd_out = 16, std::uint32_t pd_in = 8) {
    redundancy::PairParameters p;
    p.eni_content_hash = 0x0123456789ABCDEFull;
    p.cycle_time = std::chrono::milliseconds(1);
    p.cable_redundancy = true;
    p.master_pd_out_size = pd_out;
    p.master_pd_in_size = pd_in;
    p.update_slave_pd_in = true;
    p.max_acyc_frames_per_cycle = 2;
    return p;
}

// 2 slaves, 16 input bytes, 16/8 master PD bytes: one frame.
inline redundancy::CmfLayout small_layout() { return {test_parameters(), 2, 16}; }
// 33 slaves, a 5 kB input image, 600/300 master PD bytes: several frames.
inline redundancy::CmfLayout large_layout() { return {test_parameters(600, 300), 33, 5000}; }

inline redundancy::CmfPlan plan_of(const redundancy::CmfLayout& layout) { return redundancy::CmfPlan::make(layout).value(); }

// The values of one cycle, with bytes that differ per cycle and per position.
struct TestContent {
    std::vector<master::SlaveStateEntry> slaves;
    std::vector<std::uint8_t> shadow_inputs;
    std::vector<std::uint8_t> master_pd_out;
    redundancy::CmfContent content;

    TestContent(const redundancy::CmfLayout& layout, std::uint64_t cycle) {
        for (std::uint16_t i = 0; i < layout.slave_count; ++i) {
            slaves.push_back(master::SlaveStateEntry{i % 5 != 4, static_cast<std::uint8_t>(i % 3 == 0 ? 0x08 : 0x14),
                                                     static_cast<std::uint16_t>(i % 3 == 0 ? 0 : 0x001D),
                                                     static_cast<std::uint16_t>(1001 + i)});
        }
        for (std::size_t i = 0; i < layout.shadow_inputs_size; ++i) {
            shadow_inputs.push_back(static_cast<std::uint8_t>(i * 7 + cycle));
        }
        for (std::size_t i = 0; i < layout.parameters.master_pd_out_size; ++i) {
            master_pd_out.push_back(static_cast<std::uint8_t>(0xA0 ^ (i + cycle)));
        }
        content.cycle = cycle;
        content.master_state = eni::SlaveState::Op;
        content.flags = redundancy::CmfFlags{cycle % 2 == 1, cycle % 3 == 0};
        content.sender.epoch = static_cast<std::uint32_t>(cycle % 7 + 1);
        content.sender.handoff_cycle = content.flags.handoff_request ? cycle + 4 : 0;
        content.sender.slaves_reached = layout.slave_count;
        content.sender.member = wire::MacAddress{{0x02, 0x00, 0x00, 0x00, 0x00, 0x11}};
        content.sender.send_offset_ns = static_cast<std::uint32_t>(12'345 + cycle);
        content.slaves = slaves;
        content.shadow_inputs = shadow_inputs;
        content.master_pd_out = master_pd_out;
    }
    TestContent(const TestContent&) = delete;
    TestContent& operator=(const TestContent&) = delete;
};

// The frames CmfWriter sends for `content` under `layout`.
inline std::vector<SentCmfFrame> write_cmf(const redundancy::CmfLayout& layout, const redundancy::CmfContent& content) {
    redundancy::CmfWriter writer(plan_of(layout));
    CapturingSender sender;
    writer.write(content, sender).value();
    return std::move(sender.frames);
}

using FeedResult = Expected<redundancy::CmfAssembler::Outcome, redundancy::CmfError>;

// Feeds every datagram of a frame; empty when the frame does not parse.
inline std::vector<FeedResult> feed_frame(redundancy::CmfAssembler& assembler, ConstBytes frame) {
    std::vector<FeedResult> results;
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return results;
    for (auto datagram : *view) results.push_back(assembler.feed(datagram));
    return results;
}

// Feeds frames in order; the outcome of the last datagram, or the first error.
inline FeedResult feed_frames(redundancy::CmfAssembler& assembler, const std::vector<SentCmfFrame>& frames) {
    FeedResult last = redundancy::CmfAssembler::Outcome::NotCmf;
    for (const auto& frame : frames) {
        for (auto& result : feed_frame(assembler, frame.bytes)) {
            if (!result) return result;
            last = result;
        }
    }
    return last;
}

}  // namespace ecpair::test
