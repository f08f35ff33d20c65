// Merge of MAIN and RED copies (design.md §3) with hand-made copies: what
// each path means, OR of processed data, WKC sums, lost copies.

#include <array>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/master/redundant_merge.hpp"
#include "ecpair/wire/frame.hpp"

using namespace ecpair;
using namespace ecpair::master;

namespace {

// A frame with an LRD (2 bytes) and a BRD (2 bytes) carrying the given data and WKCs.
std::vector<std::uint8_t> frame_with(std::array<std::uint8_t, 2> lrd, std::uint16_t lrd_wkc,
                                     std::array<std::uint8_t, 2> brd, std::uint16_t brd_wkc) {
    std::vector<std::uint8_t> buffer(wire::kMaxFrameSize);
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    wire::FrameBuilder b(buffer, eth);
    auto l = b.append(wire::DatagramHeader{wire::Command::Lrd, 0, 0x01000000}, lrd);
    l->set_wkc(lrd_wkc);
    auto r = b.append(wire::DatagramHeader{wire::Command::Brd, 1, wire::DatagramHeader::physical(0, 0x130)}, brd);
    r->set_wkc(brd_wkc);
    const auto f = b.finish();
    return {f.begin(), f.end()};
}

struct Merged {
    MergeResult result;
    std::vector<std::uint8_t> lrd;
    std::uint16_t lrd_wkc;
    std::uint16_t brd_wkc;
};

Merged merge(const ReturnedCopy& main, const ReturnedCopy& red) {
    std::vector<std::uint8_t> out(wire::kMaxFrameSize);
    auto r = merge_copies(main, red, out);
    REQUIRE(r);
    auto view = wire::ConstFrameView::parse(std::span<const std::uint8_t>(out.data(), r->size));
    REQUIRE(view);
    auto it = view->begin();
    const auto lrd = *it;
    const auto brd = *++it;
    return {*r, {lrd.data().begin(), lrd.data().end()}, lrd.wkc(), brd.wkc()};
}

}  // namespace

TEST_CASE("where a copy comes back tells its path", "[merge]") {
    CHECK(classify(LinkRole::Main, LinkRole::Red) == CopyPath::ThroughRing);
    CHECK(classify(LinkRole::Red, LinkRole::Main) == CopyPath::Unprocessed);
    CHECK(classify(LinkRole::Main, LinkRole::Main) == CopyPath::BouncedMain);
    CHECK(classify(LinkRole::Red, LinkRole::Red) == CopyPath::BouncedRed);
}

TEST_CASE("closed ring: the MAIN copy is the result, the unprocessed RED copy adds nothing", "[merge]") {
    const auto main = frame_with({0x12, 0x34}, 5, {0x08, 0x00}, 5);
    const auto red = frame_with({0x00, 0x00}, 0, {0x00, 0x00}, 0);
    const auto m = merge({main, CopyPath::ThroughRing}, {red, CopyPath::Unprocessed});
    CHECK(m.result.complete);
    CHECK(m.result.ring_closed);
    CHECK_FALSE(m.result.ring_broken);
    CHECK(m.lrd == std::vector<std::uint8_t>{0x12, 0x34});
    CHECK(m.lrd_wkc == 5);
    CHECK(m.brd_wkc == 5);
}

TEST_CASE("broken ring: data of both processed copies is ORed and WKCs add up", "[merge]") {
    // Slaves 1..2 (before the break) filled byte 0, slaves 3..5 byte 1.
    const auto main = frame_with({0x12, 0x00}, 2, {0x08, 0x00}, 2);
    const auto red = frame_with({0x00, 0x34}, 3, {0x08, 0x00}, 3);
    const auto m = merge({main, CopyPath::BouncedMain}, {red, CopyPath::BouncedRed});
    CHECK(m.result.complete);
    CHECK(m.result.ring_broken);
    CHECK_FALSE(m.result.ring_closed);
    CHECK(m.lrd == std::vector<std::uint8_t>{0x12, 0x34});
    CHECK(m.lrd_wkc == 5);
    CHECK(m.brd_wkc == 5);
}

TEST_CASE("one copy lost on a broken ring: the result is partial", "[merge]") {
    const auto main = frame_with({0x12, 0x00}, 2, {0x08, 0x00}, 2);
    const auto m = merge({main, CopyPath::BouncedMain}, {});
    CHECK_FALSE(m.result.complete);
    CHECK(m.result.ring_broken);
    CHECK(m.lrd_wkc == 2);

    const auto red = frame_with({0x00, 0x34}, 3, {0x08, 0x00}, 3);
    const auto r = merge({}, {red, CopyPath::BouncedRed});
    CHECK_FALSE(r.result.complete);
    CHECK(r.lrd == std::vector<std::uint8_t>{0x00, 0x34});
}

TEST_CASE("only the unprocessed RED copy back: nothing was processed", "[merge]") {
    const auto red = frame_with({0x00, 0x00}, 0, {0x00, 0x00}, 0);
    const auto m = merge({}, {red, CopyPath::Unprocessed});
    CHECK_FALSE(m.result.complete);
    CHECK_FALSE(m.result.ring_broken);
    CHECK(m.lrd_wkc == 0);
}

TEST_CASE("no copy, or copies of different frames, cannot be merged", "[merge]") {
    std::vector<std::uint8_t> out(wire::kMaxFrameSize);
    CHECK_FALSE(merge_copies({}, {}, out));

    const auto main = frame_with({0, 0}, 1, {0, 0}, 1);
    std::vector<std::uint8_t> other(wire::kMaxFrameSize);
    wire::EthernetHeader eth;
    wire::FrameBuilder b(other, eth);
    b.append(wire::DatagramHeader{wire::Command::Lrd, 0, 0x01000000}, 2);
    const auto single = b.finish();
    auto r = merge_copies({main, CopyPath::BouncedMain}, {single, CopyPath::BouncedRed}, out);
    REQUIRE_FALSE(r);
    CHECK(r.error().message.find("differ") != std::string::npos);
}
