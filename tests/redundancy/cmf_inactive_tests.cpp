// process_as_inactive: the INACTIVE's in-place processing of the CMF frames
// it forwards. It adds 2 to the WKC of what it reads and 1 to what it
// writes, writes its master PD into MASTER_PD_IN and its standby status
// into STANDBY_STATUS, and leaves everything else alone. The ACTIVE's assembler then sees the partner's data and WKCs.

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>

#include "cmf_test_support.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"
#include "ecpair/wire/esc_registers.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;
using ecpair::test::TestContent;

namespace {

std::vector<std::uint8_t> pd_in_bytes(std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    std::iota(bytes.begin(), bytes.end(), std::uint8_t{0x40});
    return bytes;
}

std::vector<std::uint8_t> standby_bytes() {
    CmfStandbyStatus status;
    status.hot = true;
    status.main_link_up = true;
    status.red_link_up = true;
    status.member = wire::MacAddress{{0x02, 0, 0, 0, 0, 0x21}};
    status.epoch = 7;
    std::vector<std::uint8_t> bytes(CmfStandbyStatus::kSize);
    status.encode(bytes);
    return bytes;
}

}  // namespace

TEST_CASE("the INACTIVE adds 2 to what it reads and 1 to what it writes", "[redundancy][cmf]") {
    const CmfLayout layout = test::large_layout();
    const TestContent content(layout, 5);
    auto frames = test::write_cmf(layout, content.content);
    const auto pd_in = pd_in_bytes(layout.parameters.master_pd_in_size);
    const auto standby = standby_bytes();

    for (auto& frame : frames) {
        const auto before = frame.bytes;
        auto view = wire::FrameView::parse(frame.bytes);
        REQUIRE(view);
        CHECK(process_as_inactive(*view, pd_in, standby));
        auto original = wire::ConstFrameView::parse(before);
        auto it = original->begin();
        for (auto d : *view) {
            const auto o = *it++;
            const auto segment = CmfSegmentHeader::decode(d.data(), 0);
            REQUIRE(segment);
            if (segment->kind == CmfKind::MasterPdIn || segment->kind == CmfKind::StandbyStatus) {
                const auto& written = segment->kind == CmfKind::MasterPdIn ? pd_in : standby;
                CHECK(d.wkc() == o.wkc() + 1);
                const auto payload = d.data().subspan(CmfSegmentHeader::kSize);
                CHECK(std::ranges::equal(payload, std::span(written).subspan(segment->offset, payload.size())));
            } else {
                CHECK(d.wkc() == o.wkc() + 2);
                CHECK(std::ranges::equal(d.data(), o.data()));  // read, not written
            }
            CHECK(std::ranges::equal(d.data().first(CmfSegmentHeader::kSize), o.data().first(CmfSegmentHeader::kSize)));
        }
    }

    // What returns to the ACTIVE: the partner's PD and its WKCs.
    CmfAssembler assembler(test::plan_of(layout));
    const auto outcome = test::feed_frames(assembler, frames);
    REQUIRE(outcome);
    CHECK(*outcome == CmfAssembler::Outcome::Completed);
    CHECK(std::ranges::equal(assembler.content().master_pd_in, pd_in));
    CHECK(std::ranges::equal(assembler.content().master_pd_out, content.master_pd_out));
    CHECK(CmfStandbyStatus::decode(assembler.content().standby_status) == CmfStandbyStatus::decode(standby));
    CHECK(assembler.working_counters().lowest_read == 2);
    CHECK(assembler.working_counters().lowest_write == std::optional<std::uint16_t>(1));
}

TEST_CASE("a shorter master PD in leaves the rest of the section as sent", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();  // 8 bytes of MASTER_PD_IN
    const TestContent content(layout, 2);
    auto frames = test::write_cmf(layout, content.content);
    const std::vector<std::uint8_t> pd_in{0xAA, 0xBB, 0xCC};
    auto view = wire::FrameView::parse(frames[0].bytes);
    REQUIRE(process_as_inactive(*view, pd_in, {}));

    CmfAssembler assembler(test::plan_of(layout));
    REQUIRE(test::feed_frames(assembler, frames).value() == CmfAssembler::Outcome::Completed);
    CHECK(std::ranges::equal(assembler.content().master_pd_in,
                             std::vector<std::uint8_t>{0xAA, 0xBB, 0xCC, 0, 0, 0, 0, 0}));
}

TEST_CASE("frames without CMF datagrams are not touched", "[redundancy][cmf]") {
    std::array<std::uint8_t, 128> buffer{};
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    wire::FrameBuilder builder(buffer, eth);
    wire::DatagramHeader lrd;
    lrd.command = wire::Command::Lrd;
    lrd.address = 0x10000;
    REQUIRE(builder.append(lrd, 8));
    // A NOP at the CMF address whose data is not a CMF segment (no magic).
    wire::DatagramHeader nop;
    nop.address = wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo);
    REQUIRE(builder.append(nop, 20));
    const Bytes frame = builder.finish();
    const std::vector<std::uint8_t> before(frame.begin(), frame.end());

    auto view = wire::FrameView::parse(frame);
    REQUIRE(view);
    CHECK_FALSE(process_as_inactive(*view, {}, {}));
    CHECK(std::ranges::equal(frame, before));
}

TEST_CASE("CMF datagrams of an unknown format version are forwarded without credit", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    const TestContent content(layout, 2);
    auto frames = test::write_cmf(layout, content.content);
    auto view = wire::FrameView::parse(frames[0].bytes);
    for (auto d : *view) d.data()[2] = 3;  // a future version
    const std::vector<std::uint8_t> before = frames[0].bytes;
    CHECK_FALSE(process_as_inactive(*view, std::vector<std::uint8_t>(8, 0xFF), standby_bytes()));
    CHECK(frames[0].bytes == before);
}

TEST_CASE("the standby status encodes every flag where WIRE_FORMAT.md says", "[redundancy][cmf]") {
    CmfStandbyStatus status;
    status.hot = true;
    status.forced = false;
    status.partner_differs = true;
    status.switchover_requested = false;
    status.handoff_acknowledged = true;
    status.main_link_up = true;
    status.red_link_up = false;
    status.member = wire::MacAddress{{0x02, 0x00, 0x00, 0x00, 0x00, 0x21}};
    status.handoff_cycle_low = 0x01020304;
    status.epoch = 9;
    std::array<std::uint8_t, CmfStandbyStatus::kSize> bytes{};
    status.encode(bytes);
    CHECK(to_hex(bytes) == "35" "00" "020000000021" "04030201" "09000000");
    CHECK(CmfStandbyStatus::decode(bytes) == status);
    bytes[0] |= 0x80;  // a reserved bit is ignored
    bytes[1] = 0xFF;
    CHECK(CmfStandbyStatus::decode(bytes) == status);
}
