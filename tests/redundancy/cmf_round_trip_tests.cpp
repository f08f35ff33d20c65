// CmfWriter -> frames -> CmfAssembler: what goes in comes out, for a small
// layout (one frame) and a large one (33 slaves, a 5 kB input image, several
// frames); the frames respect the EtherCAT size limits and are as few as the
// plan allows; the first datagram is laid out byte by byte as documented.

#include <catch2/catch.hpp>

#include <algorithm>

#include "cmf_test_support.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;
using ecpair::test::TestContent;
using Outcome = CmfAssembler::Outcome;

namespace {

void check_round_trip(const CmfLayout& layout, const TestContent& sent, const CmfAssembler& assembler) {
    REQUIRE(assembler.has_complete());
    const CmfContent& got = assembler.content();
    CHECK(got.cycle == sent.content.cycle);
    CHECK(got.master_state == sent.content.master_state);
    CHECK(got.flags == sent.content.flags);
    CHECK(got.sender == sent.content.sender);
    CHECK(got.standby_status.size() == CmfStandbyStatus::kSize);
    CHECK(std::ranges::all_of(got.standby_status, [](std::uint8_t b) { return b == 0; }));
    CHECK(std::ranges::equal(got.slaves, sent.slaves));
    CHECK(std::ranges::equal(got.shadow_inputs, sent.shadow_inputs));
    CHECK(std::ranges::equal(got.master_pd_out, sent.master_pd_out));
    CHECK(got.master_pd_in.size() == layout.parameters.master_pd_in_size);
    CHECK(std::ranges::all_of(got.master_pd_in, [](std::uint8_t b) { return b == 0; }));

    const CmfHeader& h = assembler.header();
    CHECK(h.cycle == sent.content.cycle);
    CHECK(h.parameters == layout.parameters);
    CHECK(h.fingerprint == layout.parameters.fingerprint());
    CHECK(h.layout() == layout);
    CHECK(h.part_count == assembler.plan().parts().size());
    CHECK(assembler.working_counters().lowest_read == 0);  // straight from the writer: nobody read it yet
}

}  // namespace

TEST_CASE("a small CMF is one frame and decodes to what was written", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    const TestContent sent(layout, 41);
    const auto frames = test::write_cmf(layout, sent.content);
    REQUIRE(frames.size() == 1);
    CHECK(frames[0].index == 0);

    CmfAssembler assembler(test::plan_of(layout));
    const auto outcome = test::feed_frames(assembler, frames);
    REQUIRE(outcome);
    CHECK(*outcome == Outcome::Completed);
    check_round_trip(layout, sent, assembler);
}

TEST_CASE("the HEADER datagram is laid out byte by byte as WIRE_FORMAT.md says", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    const TestContent sent(layout, 0x1'0000'0029ull);  // cycle > 32 bits: the segment carries the low half
    const auto frames = test::write_cmf(layout, sent.content);
    REQUIRE(frames.size() == 1);
    auto view = wire::ConstFrameView::parse(frames[0].bytes);
    REQUIRE(view);
    // HEADER 92 + 2 slaves x 6 + 16 inputs + 16 PD out + 8 PD in + 16 standby status: six datagrams.
    REQUIRE(view->datagram_count() == 6);
    const auto first = *view->begin();
    CHECK(first.command() == wire::Command::Nop);
    CHECK(first.address() == 0x41550000u);  // ADP 0, ADO 0x4155
    CHECK(first.length() == CmfSegmentHeader::kSize + CmfHeader::kSize);
    CHECK(first.wkc() == 0);
    const auto data = first.data();
    // segment: "CM", version 2, kind HEADER, part 0 of 6, offset 0, cycle low 0x00000029
    CHECK(to_hex(data.first(16)) == "434d02010000060000000000" "29000000");
    // header: version 2, state OP, flags ring broken (odd cycle) and hand-off (cycle divisible by 3),
    // cycle 0x100000029, 2 slaves, 6 parts, sizes 12 / 16 / 16 / 8
    CHECK(to_hex(data.subspan(16, 32)) ==
          "0208" "0300" "2900000001000000" "0200" "0600" "0c000000" "10000000" "10000000" "08000000");
    CHECK(to_hex(data.subspan(48, 28)) == "efcdab896745230140420f0000000000100000000800000002000500");
    CHECK(load_le<std::uint64_t>(data, 76) == layout.parameters.fingerprint());
    // sender: epoch (cycle % 7 + 1 = 4), hand-off at cycle + 4, 2 slaves reached, MAIN MAC,
    // send offset 12345 + cycle (low 32 bits)
    CHECK(to_hex(data.subspan(84, 24)) ==
          "04000000" "2d00000001000000" "0200" "020000000011" "62300000");

    // The slave entries follow in the second datagram: present, AL status, station address, status code.
    const auto second = *std::next(view->begin());
    CHECK(to_hex(second.data().subspan(16)) == "0108e9030000" "0114ea031d00");
}

TEST_CASE("flag bit 2 of the HEADER says the hand-off is committed, and decodes back", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    TestContent sent(layout, 0x30);
    sent.content.flags = CmfFlags{false, true, true};
    const auto frames = test::write_cmf(layout, sent.content);
    REQUIRE(frames.size() == 1);
    auto view = wire::ConstFrameView::parse(frames[0].bytes);
    REQUIRE(view);
    const auto data = (*view->begin()).data();
    CHECK(to_hex(data.subspan(CmfSegmentHeader::kSize + 2, 2)) == "0600");
    const auto header = CmfHeader::decode(data.subspan(CmfSegmentHeader::kSize), 0);
    REQUIRE(header);
    CHECK(header->flags.handoff_request);
    CHECK(header->flags.handoff_committed);
    CHECK_FALSE(header->flags.ring_broken);
}

TEST_CASE("a large CMF spans several frames within EtherCAT's limits and round-trips", "[redundancy][cmf]") {
    const CmfLayout layout = test::large_layout();
    const auto plan = test::plan_of(layout);
    const TestContent sent(layout, 7);
    const auto frames = test::write_cmf(layout, sent.content);

    REQUIRE(frames.size() == plan.frame_count());
    CHECK(frames.size() >= 4);
    std::size_t datagrams = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        CHECK(frames[i].index == i);
        CHECK(frames[i].bytes.size() <= wire::kMaxFrameSize);
        auto view = wire::ConstFrameView::parse(frames[i].bytes);
        REQUIRE(view);
        std::size_t used = 0;
        for (auto d : *view) {
            CHECK(d.length() <= wire::kMaxDatagramData);
            CHECK(is_cmf_datagram(d));
            used += d.size();
            ++datagrams;
        }
        // As few frames as possible: only the last frame may leave room for another datagram.
        if (i + 1 < frames.size()) CHECK(used + wire::kDatagramOverhead + CmfSegmentHeader::kSize >= wire::kMaxEcatPayload);
    }
    CHECK(datagrams == plan.parts().size());

    CmfAssembler assembler(plan);
    const auto outcome = test::feed_frames(assembler, frames);
    REQUIRE(outcome);
    CHECK(*outcome == Outcome::Completed);
    check_round_trip(layout, sent, assembler);
}

TEST_CASE("consecutive cycles complete one after the other", "[redundancy][cmf]") {
    const CmfLayout layout = test::large_layout();
    CmfWriter writer(test::plan_of(layout));
    CmfAssembler assembler(test::plan_of(layout));
    for (std::uint64_t cycle = 100; cycle < 105; ++cycle) {
        const TestContent sent(layout, cycle);
        test::CapturingSender sender;
        REQUIRE(writer.write(sent.content, sender).value() == writer.plan().frame_count());
        const auto outcome = test::feed_frames(assembler, sender.frames);
        REQUIRE(outcome);
        CHECK(*outcome == Outcome::Completed);
        check_round_trip(layout, sent, assembler);
    }
    CHECK(assembler.counters().completed == 5);
    CHECK(assembler.counters().abandoned == 0);
}

TEST_CASE("content that does not fit the layout is refused and nothing is sent", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfWriter writer(test::plan_of(layout));
    const TestContent good(layout, 1);
    using What = CmfWriteError::What;

    auto refused = [&](CmfContent content, What what) {
        test::CapturingSender sender;
        const auto result = writer.write(content, sender);
        REQUIRE_FALSE(result);
        CHECK(result.error().what == what);
        CHECK(sender.frames.empty());
        return result.error().describe();
    };
    CmfContent content = good.content;
    content.slaves = content.slaves.first(1);
    CHECK(refused(content, What::SlaveCount) == "CMF content has 1 slave entries, the layout 2");
    content = good.content;
    content.shadow_inputs = content.shadow_inputs.first(3);
    CHECK(refused(content, What::ShadowInputsSize) == "CMF content has 3 shadow input bytes, the layout 16");
    content = good.content;
    content.master_pd_out = {};
    CHECK(refused(content, What::MasterPdOutSize) == "CMF content has 0 master PD out bytes, the layout 16");
}

TEST_CASE("a sender whose buffer cannot hold a CMF frame gets nothing", "[redundancy][cmf]") {
    class SmallSender final : public master::FrameSender {
    public:
        Bytes buffer() override { return buffer_; }
        wire::EthernetHeader ethernet() const override { return {}; }
        void send(std::uint16_t, Bytes) override { ++sent; }
        int sent = 0;

    private:
        std::array<std::uint8_t, 100> buffer_{};
    };
    const CmfLayout layout = test::large_layout();
    CmfWriter writer(test::plan_of(layout));
    const TestContent content(layout, 1);
    SmallSender sender;
    const auto result = writer.write(content.content, sender);
    REQUIRE_FALSE(result);
    CHECK(result.error().what == CmfWriteError::What::SenderBufferTooSmall);
    CHECK(sender.sent == 0);
}

TEST_CASE("the plan cuts sections greedily and refuses layouts beyond 65535 parts", "[redundancy][cmf]") {
    const auto plan = test::plan_of(test::large_layout());
    CHECK(CmfPlan::count_parts(test::large_layout()) == plan.parts().size());
    // Sections appear in kind order, contiguous, each covered exactly.
    std::uint32_t expected_offset = 0;
    CmfKind kind = CmfKind::Header;
    for (const CmfPart& part : plan.parts()) {
        if (part.kind != kind) {
            CHECK(expected_offset == test::large_layout().section_size(kind));
            CHECK(static_cast<int>(part.kind) > static_cast<int>(kind));
            kind = part.kind;
            expected_offset = 0;
        }
        CHECK(part.offset == expected_offset);
        CHECK(part.length > 0);
        expected_offset += part.length;
    }
    CHECK(kind == CmfKind::StandbyStatus);
    CHECK(expected_offset == CmfStandbyStatus::kSize);

    CmfLayout huge = test::small_layout();
    huge.parameters.master_pd_out_size = 200u << 20;
    const auto refused = CmfPlan::make(huge);
    REQUIRE_FALSE(refused);
    CHECK_THAT(refused.error(), Catch::Contains("more than 65535 datagrams"));
}
