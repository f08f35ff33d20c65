// CmfAssembler on its own: parts placed in any order and with copies
// (MAIN and RED), cycles that overtake or restart, and every kind of
// malformed or foreign datagram refused with a typed error and its offset.

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "cmf_test_support.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"
#include "ecpair/wire/esc_registers.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;
using ecpair::test::TestContent;
using Outcome = CmfAssembler::Outcome;

namespace {

// One datagram of a written CMF, kept as the bytes of a frame of its own so
// that tests can feed parts one by one and tamper with them.
struct Part {
    std::vector<std::uint8_t> frame;  // the whole frame the datagram came in
    std::size_t datagram = 0;         // its place in that frame

    wire::DatagramView view() {
        auto parsed = wire::FrameView::parse(frame);
        auto it = parsed->begin();
        std::advance(it, static_cast<std::ptrdiff_t>(datagram));
        return *it;
    }
};

std::vector<Part> parts_of(const std::vector<test::SentCmfFrame>& frames) {
    std::vector<Part> parts;
    for (const auto& f : frames) {
        const auto view = wire::ConstFrameView::parse(f.bytes);
        for (std::size_t i = 0; i < view->datagram_count(); ++i) parts.push_back(Part{f.bytes, i});
    }
    return parts;
}

std::vector<Part> written_parts(const CmfLayout& layout, std::uint64_t cycle) {
    const TestContent content(layout, cycle);
    return parts_of(test::write_cmf(layout, content.content));
}

Outcome feed_ok(CmfAssembler& assembler, Part& part) {
    const auto result = assembler.feed(part.view());
    REQUIRE(result);
    return *result;
}

CmfError feed_error(CmfAssembler& assembler, Part& part) {
    const auto result = assembler.feed(part.view());
    REQUIRE_FALSE(result);
    return result.error();
}

}  // namespace

TEST_CASE("parts complete a cycle in any order, copies included", "[redundancy][cmf]") {
    const CmfLayout layout = test::large_layout();
    CmfAssembler assembler(test::plan_of(layout));
    auto parts = written_parts(layout, 9);
    // The MAIN and RED copies of every part, shuffled.
    auto copies = parts;
    copies.insert(copies.end(), parts.begin(), parts.end());
    std::mt19937 rng(1234);
    std::shuffle(copies.begin(), copies.end(), rng);

    std::size_t completed_at = 0;
    for (std::size_t i = 0; i < copies.size(); ++i) {
        const Outcome outcome = feed_ok(assembler, copies[i]);
        if (outcome == Outcome::Completed) completed_at = i + 1;
    }
    CHECK(assembler.counters().completed == 1);
    CHECK(assembler.counters().duplicates == parts.size());
    CHECK(completed_at >= parts.size());
    const TestContent expected(layout, 9);
    CHECK(std::ranges::equal(assembler.content().shadow_inputs, expected.shadow_inputs));
    CHECK(std::ranges::equal(assembler.content().slaves, expected.slaves));
}

TEST_CASE("a part held already is a duplicate and the completed cycle is not completed again", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfAssembler assembler(test::plan_of(layout));
    auto parts = written_parts(layout, 3);
    CHECK(feed_ok(assembler, parts[2]) == Outcome::Stored);
    CHECK(feed_ok(assembler, parts[2]) == Outcome::Duplicate);
    for (std::size_t i : {0u, 1u, 3u, 4u}) CHECK(feed_ok(assembler, parts[i]) == Outcome::Stored);
    CHECK(feed_ok(assembler, parts[5]) == Outcome::Completed);
    for (auto& part : parts) CHECK(feed_ok(assembler, part) == Outcome::Duplicate);
    CHECK(assembler.counters().completed == 1);
}

TEST_CASE("a newer cycle abandons the incomplete one; older parts are stale", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfAssembler assembler(test::plan_of(layout));
    auto old_parts = written_parts(layout, 10);
    auto new_parts = written_parts(layout, 11);
    CHECK(feed_ok(assembler, old_parts[0]) == Outcome::Stored);
    CHECK(feed_ok(assembler, new_parts[1]) == Outcome::Stored);
    CHECK(assembler.counters().abandoned == 1);
    CHECK(feed_ok(assembler, old_parts[2]) == Outcome::Stale);
    for (std::size_t i : {0u, 2u, 3u}) CHECK(feed_ok(assembler, new_parts[i]) == Outcome::Stored);
    CHECK(feed_ok(assembler, new_parts[4]) == Outcome::Completed);
    CHECK(assembler.content().cycle == 11);
    // The content stays that of cycle 11 while cycle 12 is being assembled.
    auto next = written_parts(layout, 12);
    CHECK(feed_ok(assembler, next[2]) == Outcome::Stored);
    CHECK(assembler.content().cycle == 11);
    const TestContent eleven(layout, 11);
    CHECK(std::ranges::equal(assembler.content().shadow_inputs, eleven.shadow_inputs));
}

TEST_CASE("a partner whose cycle counter restarted is followed", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfAssembler assembler(test::plan_of(layout));
    for (auto& part : written_parts(layout, 5000)) (void)feed_ok(assembler, part);
    REQUIRE(assembler.content().cycle == 5000);
    // Within the stale window: stale. Further back: a restart, assembled.
    auto recent = written_parts(layout, 5000 - CmfAssembler::kStaleWindow);
    CHECK(feed_ok(assembler, recent[0]) == Outcome::Stale);
    Outcome last = Outcome::NotCmf;
    for (auto& part : written_parts(layout, 1)) last = feed_ok(assembler, part);
    CHECK(last == Outcome::Completed);
    CHECK(assembler.content().cycle == 1);
}

TEST_CASE("datagrams that are not CMF are passed over", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfAssembler assembler(test::plan_of(layout));
    auto parts = written_parts(layout, 1);
    auto other_ado = parts[0];
    other_ado.view().set_address(wire::DatagramHeader::physical(0, 0x4156));
    CHECK(feed_ok(assembler, other_ado) == Outcome::NotCmf);
    auto not_nop = parts[0];
    not_nop.view().bytes()[0] = static_cast<std::uint8_t>(wire::Command::Fprd);
    CHECK(feed_ok(assembler, not_nop) == Outcome::NotCmf);
    CHECK_FALSE(is_cmf_datagram(not_nop.view()));
    CHECK(is_cmf_datagram(parts[0].view()));
}

TEST_CASE("malformed CMF datagrams get a typed error with the frame offset", "[redundancy][cmf]") {
    const CmfLayout layout = test::small_layout();
    CmfAssembler assembler(test::plan_of(layout));
    auto parts = written_parts(layout, 1);
    // The first datagram's data starts after Ethernet (14), EtherCAT (2) and datagram (10) headers.
    constexpr std::size_t kData = 26;

    SECTION("bad magic") {
        auto p = parts[1];
        p.view().data()[0] = 'X';
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::BadMagic);
        CHECK_FALSE(is_cmf_datagram(p.view()));
    }
    SECTION("other format version") {
        auto p = parts[0];
        p.view().data()[2] = 1;  // the version before
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::UnsupportedVersion);
        CHECK(e.offset == kData + 2);
        CHECK(e.found == 1);
        CHECK(e.describe() == "CMF UnsupportedVersion at frame offset 28: found 0x1, expected 0x2");
    }
    SECTION("header payload with another format version") {
        auto p = parts[0];
        p.view().data()[16] = 7;
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::UnsupportedVersion);
        CHECK(e.offset == kData + 16);
    }
    SECTION("unknown section kind") {
        auto p = parts[0];
        p.view().data()[3] = 9;
        CHECK(feed_error(assembler, p).code == CmfErrc::UnknownKind);
    }
    SECTION("part index beyond the part count") {
        auto p = parts[3];
        store_le<std::uint16_t>(p.view().data(), 4, 5);
        CHECK(feed_error(assembler, p).code == CmfErrc::BadPlacement);
    }
    SECTION("a part whose offset is not where the layout puts it") {
        auto p = parts[3];
        store_le<std::uint32_t>(p.view().data(), 8, 4);
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::BadPlacement);
        CHECK(e.found == 4);
        CHECK(e.expected == 0);
    }
    SECTION("a part of another kind than the layout says") {
        auto p = parts[2];
        p.view().data()[3] = static_cast<std::uint8_t>(CmfKind::MasterPdOut);
        CHECK(feed_error(assembler, p).code == CmfErrc::BadPlacement);
    }
    SECTION("a partner with another part count") {
        auto p = parts[2];
        store_le<std::uint16_t>(p.view().data(), 6, 9);
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::LayoutMismatch);
        CHECK(e.found == 9);
        CHECK(e.expected == 6);
    }
    SECTION("truncated segment header") {
        // A CMF datagram too short for its segment header: magic only.
        std::vector<std::uint8_t> frame = parts[0].frame;
        auto view = wire::FrameView::parse(frame);
        wire::EthernetHeader eth = view->ethernet();
        std::array<std::uint8_t, 64> buffer{};
        wire::FrameBuilder builder(buffer, eth);
        wire::DatagramHeader h;
        h.address = wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo);
        const std::array<std::uint8_t, 4> data{'C', 'M', 1, 1};
        REQUIRE(builder.append(h, data));
        const Bytes built = builder.finish();
        Part p{{built.begin(), built.end()}, 0};
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::Truncated);
        CHECK(e.found == 4);
        CHECK(e.expected == CmfSegmentHeader::kSize);
    }
    SECTION("a header whose fingerprint is not its parameters'") {
        auto p = parts[0];
        p.view().data()[16 + 60] ^= 0x01;
        CHECK(feed_error(assembler, p).code == CmfErrc::FingerprintCorrupt);
    }
    SECTION("a header with reserved parameter bits set") {
        auto p = parts[0];
        p.view().data()[16 + 32 + 26] |= 0x80;  // an unknown flag
        const auto e = feed_error(assembler, p);
        CHECK(e.code == CmfErrc::ReservedBitsSet);
        CHECK(e.offset == kData + 16 + 32 + 26);
    }
    SECTION("a header whose sizes contradict each other") {
        auto p = parts[0];
        store_le<std::uint32_t>(p.view().data(), 16 + 16, 13);  // slave state size for 2 slaves is 12
        CHECK(feed_error(assembler, p).code == CmfErrc::InconsistentHeader);
    }
    SECTION("a header with no AL state for the master") {
        auto p = parts[0];
        p.view().data()[16 + 1] = 5;
        CHECK(feed_error(assembler, p).code == CmfErrc::InvalidMasterState);
    }
    SECTION("a header whose cycle is not its segment's") {
        auto p = parts[0];
        p.view().data()[12] ^= 0x01;
        CHECK(feed_error(assembler, p).code == CmfErrc::CycleMismatch);
    }
    CHECK(assembler.counters().errors == 1);
    CHECK_FALSE(assembler.has_complete());
}

TEST_CASE("a partner with other parameters is refused, its header kept for the diagnosis", "[redundancy][cmf]") {
    const CmfLayout ours = test::small_layout();
    CmfLayout theirs = ours;
    theirs.parameters.cycle_time = std::chrono::microseconds(500);
    CmfAssembler assembler(test::plan_of(ours));
    auto parts = written_parts(theirs, 1);
    const auto e = feed_error(assembler, parts[0]);
    CHECK(e.code == CmfErrc::PartnerDiffers);
    CHECK(e.found == theirs.parameters.fingerprint());
    CHECK(e.expected == ours.parameters.fingerprint());
    REQUIRE(assembler.last_header());
    CHECK(differences(ours.parameters, assembler.last_header()->parameters) ==
          std::vector<std::string>{"cycle time 1000 µs vs 500 µs"});
    CHECK_FALSE(assembler.has_complete());
}

TEST_CASE("a partner with the same parameters but another image layout is refused", "[redundancy][cmf]") {
    const CmfLayout ours = test::small_layout();
    CmfLayout theirs = ours;
    theirs.slave_count = 3;
    CmfAssembler assembler(test::plan_of(ours));
    auto parts = written_parts(theirs, 1);
    const auto e = feed_error(assembler, parts[0]);
    CHECK(e.code == CmfErrc::LayoutMismatch);
    CHECK(e.found == 3);
    CHECK(e.expected == 2);
}
