// Merge of MAIN and RED copies (design.md §3) with hand-made copies: what
// each path means, WKC sums, IRQs ORed, lost copies, and for a broken ring
// (two processed halves) the rule of every command class: writes come back
// as sent, one addressed slave's answer is taken from the copy that counted
// it (never the bytes the other half echoes), ARMW/FRMW from the copy that
// changed, broadcast reads OR, logical datagrams bit by bit.

#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/master/redundant_merge.hpp"
#include "ecpair/wire/frame.hpp"

using namespace ecpair;
using namespace ecpair::master;
using Data = std::vector<std::uint8_t>;

namespace {

// One datagram of a hand-made copy.
struct Datagram {
    wire::Command command = wire::Command::Lrd;
    std::uint32_t address = 0x01000000;
    Data data;
    std::uint16_t wkc = 0;
    std::uint16_t irq = 0;
};

Data frame_of(const std::vector<Datagram>& datagrams) {
    Data buffer(wire::kMaxFrameSize);
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    wire::FrameBuilder b(buffer, eth);
    std::uint8_t index = 0;
    for (const auto& d : datagrams) {
        wire::DatagramHeader header{d.command, index++, d.address};
        header.irq = d.irq;
        auto view = b.append(header, d.data);
        REQUIRE(view);
        view->set_wkc(d.wkc);
    }
    const auto f = b.finish();
    return {f.begin(), f.end()};
}

struct Merged {
    MergeResult result;
    std::vector<Datagram> datagrams;
};

Merged merge(const Data& sent, const ReturnedCopy& main, const ReturnedCopy& red) {
    Data out(wire::kMaxFrameSize);
    auto r = merge_copies(sent, main, red, out);
    REQUIRE(r);
    auto view = wire::ConstFrameView::parse(std::span<const std::uint8_t>(out.data(), r->size));
    REQUIRE(view);
    Merged m{*r, {}};
    for (const auto d : *view) {
        m.datagrams.push_back({d.command(), d.address(), {d.data().begin(), d.data().end()}, d.wkc(), d.irq()});
    }
    return m;
}

// One datagram sent as `sent`, its halves of a ring broken in the middle.
Datagram merge_broken(wire::Command command, const Data& sent, const Data& main_data, std::uint16_t main_wkc,
                      const Data& red_data, std::uint16_t red_wkc) {
    const auto s = frame_of({{command, 0x01000000, sent}});
    const auto main = frame_of({{command, 0x01000000, main_data, main_wkc}});
    const auto red = frame_of({{command, 0x01000000, red_data, red_wkc}});
    auto m = merge(s, {main, CopyPath::BouncedMain}, {red, CopyPath::BouncedRed});
    CHECK(m.result.complete);
    CHECK(m.result.ring_broken);
    REQUIRE(m.datagrams.size() == 1);
    CHECK(m.datagrams[0].wkc == main_wkc + red_wkc);
    return m.datagrams[0];
}

// A frame with an LRD (2 bytes) and a BRD (2 bytes) carrying the given data and WKCs.
Data lrd_brd(Data lrd, std::uint16_t lrd_wkc, Data brd, std::uint16_t brd_wkc) {
    return frame_of({{wire::Command::Lrd, 0x01000000, std::move(lrd), lrd_wkc},
                     {wire::Command::Brd, wire::DatagramHeader::physical(0, 0x130), std::move(brd), brd_wkc}});
}
// The LRD + BRD frame as the master sent it.
Data lrd_brd_sent() { return lrd_brd({0, 0}, 0, {0, 0}, 0); }

}  // namespace

TEST_CASE("where a copy comes back tells its path", "[merge]") {
    CHECK(classify(LinkRole::Main, LinkRole::Red) == CopyPath::ThroughRing);
    CHECK(classify(LinkRole::Red, LinkRole::Main) == CopyPath::Unprocessed);
    CHECK(classify(LinkRole::Main, LinkRole::Main) == CopyPath::BouncedMain);
    CHECK(classify(LinkRole::Red, LinkRole::Red) == CopyPath::BouncedRed);
}

TEST_CASE("every command has the merge rule of its class", "[merge]") {
    using wire::Command;
    CHECK(merge_rule_of(Command::Nop) == MergeRule::AsSent);
    for (const auto c : {Command::Apwr, Command::Fpwr, Command::Bwr, Command::Lwr}) {
        CHECK(merge_rule_of(c) == MergeRule::AsSent);
    }
    for (const auto c : {Command::Aprd, Command::Fprd, Command::Aprw, Command::Fprw}) {
        CHECK(merge_rule_of(c) == MergeRule::CountedCopy);
    }
    for (const auto c : {Command::Armw, Command::Frmw}) CHECK(merge_rule_of(c) == MergeRule::ChangedCopy);
    for (const auto c : {Command::Brd, Command::Brw}) CHECK(merge_rule_of(c) == MergeRule::Or);
    for (const auto c : {Command::Lrd, Command::Lrw}) CHECK(merge_rule_of(c) == MergeRule::ChangedBits);
    CHECK(merge_rule_of(static_cast<Command>(0x1F)) == MergeRule::AsSent);
}

TEST_CASE("closed ring: the MAIN copy is the result, the unprocessed RED copy adds nothing", "[merge]") {
    const auto main = lrd_brd({0x12, 0x34}, 5, {0x08, 0x00}, 5);
    const auto red = lrd_brd({0x00, 0x00}, 0, {0x00, 0x00}, 0);
    const auto m = merge(lrd_brd_sent(), {main, CopyPath::ThroughRing}, {red, CopyPath::Unprocessed});
    CHECK(m.result.complete);
    CHECK(m.result.ring_closed);
    CHECK_FALSE(m.result.ring_broken);
    CHECK(m.datagrams[0].data == Data{0x12, 0x34});
    CHECK(m.datagrams[0].wkc == 5);
    CHECK(m.datagrams[1].wkc == 5);
}

TEST_CASE("closed ring: an APRW's unprocessed RED copy, which still carries the written bytes, changes nothing",
          "[merge]") {
    const Data written{0xAA, 0xBB};
    const auto sent = frame_of({{wire::Command::Aprw, 0x01000000, written}});
    const auto main = frame_of({{wire::Command::Aprw, 0x01000000, {0x01, 0x02}, 3}});
    const auto red = frame_of({{wire::Command::Aprw, 0x01000000, written, 0}});
    const auto m = merge(sent, {main, CopyPath::ThroughRing}, {red, CopyPath::Unprocessed});
    CHECK(m.datagrams[0].data == Data{0x01, 0x02});
    CHECK(m.datagrams[0].wkc == 3);
}

TEST_CASE("broken ring: LRD and BRD halves make one pass and WKCs add up", "[merge]") {
    // Slaves 1..2 (before the break) filled byte 0, slaves 3..5 byte 1.
    const auto main = lrd_brd({0x12, 0x00}, 2, {0x08, 0x00}, 2);
    const auto red = lrd_brd({0x00, 0x34}, 3, {0x08, 0x00}, 3);
    const auto m = merge(lrd_brd_sent(), {main, CopyPath::BouncedMain}, {red, CopyPath::BouncedRed});
    CHECK(m.result.complete);
    CHECK(m.result.ring_broken);
    CHECK_FALSE(m.result.ring_closed);
    CHECK(m.datagrams[0].data == Data{0x12, 0x34});
    CHECK(m.datagrams[0].wkc == 5);
    CHECK(m.datagrams[1].wkc == 5);
}

TEST_CASE("broken ring, writes (APWR FPWR BWR LWR, NOP): the data as sent", "[merge]") {
    const auto command =
        GENERATE(wire::Command::Apwr, wire::Command::Fpwr, wire::Command::Bwr, wire::Command::Lwr, wire::Command::Nop);
    INFO("command " << static_cast<int>(command));
    const Data sent{0xA5, 0x5A, 0x01};
    const auto d = merge_broken(command, sent, sent, 1, sent, 2);
    CHECK(d.data == sent);
}

TEST_CASE("broken ring, one addressed slave (APRD FPRD): the answer of the copy that counted it", "[merge]") {
    const auto command = GENERATE(wire::Command::Aprd, wire::Command::Fprd);
    INFO("command " << static_cast<int>(command));
    const Data zeros{0, 0};
    SECTION("the slave is behind the break") {
        CHECK(merge_broken(command, zeros, zeros, 0, {0x12, 0x34}, 1).data == Data{0x12, 0x34});
    }
    SECTION("the slave is before the break") {
        CHECK(merge_broken(command, zeros, {0x12, 0x34}, 1, zeros, 0).data == Data{0x12, 0x34});
    }
    SECTION("the slave answers 0 where the master sent something else") {
        CHECK(merge_broken(command, {0xFF, 0xFF}, {0xFF, 0xFF}, 0, {0x00, 0x00}, 1).data == Data{0x00, 0x00});
    }
}

TEST_CASE("broken ring, APRW FPRW: the read value, never ORed with the written bytes the other half echoes",
          "[merge]") {
    const auto command = GENERATE(wire::Command::Aprw, wire::Command::Fprw);
    INFO("command " << static_cast<int>(command));
    const Data written{0xAA, 0xBB};
    const Data read{0x01, 0x02};
    SECTION("the slave is behind the break") {
        CHECK(merge_broken(command, written, written, 0, read, 3).data == read);
    }
    SECTION("the slave is before the break") {
        CHECK(merge_broken(command, written, read, 3, written, 0).data == read);
    }
}

TEST_CASE("broken ring, ARMW FRMW: the reader's value from whichever half it is in", "[merge]") {
    const auto command = GENERATE(wire::Command::Armw, wire::Command::Frmw);
    INFO("command " << static_cast<int>(command));
    // The master sends its own time; the reference clock replaces it, every other slave takes it (and counts).
    const Data sent{0x10, 0x20, 0x30, 0x40};
    const Data reference{0x99, 0x88, 0x77, 0x66};
    SECTION("the reference clock before the break") {
        CHECK(merge_broken(command, sent, reference, 2, sent, 3).data == reference);
    }
    SECTION("the reference clock behind the break") {
        CHECK(merge_broken(command, sent, sent, 2, reference, 3).data == reference);
    }
}

TEST_CASE("broken ring, BRD BRW: every slave's bits ORed", "[merge]") {
    const auto command = GENERATE(wire::Command::Brd, wire::Command::Brw);
    INFO("command " << static_cast<int>(command));
    CHECK(merge_broken(command, {0x00, 0x01}, {0x08, 0x01}, 2, {0x04, 0x01}, 3).data == Data{0x0C, 0x01});
}

TEST_CASE("broken ring, LRD: each slave's bits, also two slaves sharing a byte", "[merge]") {
    // Slave A (before the break) has bits 0-3 of byte 0, slave B (behind it) bits 4-7 and byte 1.
    CHECK(merge_broken(wire::Command::Lrd, {0, 0}, {0x05, 0x00}, 1, {0xA0, 0x42}, 1).data == Data{0xA5, 0x42});
}

TEST_CASE("broken ring, LRW: inputs from the half that read them, outputs as sent, also where they overlap",
          "[merge]") {
    // Bytes 0-1: outputs sent; byte 2: slave A's inputs; byte 1 is also slave B's input
    // (overlapping in- and outputs, one logical address for both).
    const Data sent{0xAA, 0xBB, 0x00};
    const Data main_half{0xAA, 0xBB, 0x12};  // slave A read byte 2
    const Data red_half{0xAA, 0x44, 0x00};   // slave B took 0xBB and put its input 0x44 there
    CHECK(merge_broken(wire::Command::Lrw, sent, main_half, 3, red_half, 3).data == Data{0xAA, 0x44, 0x12});
}

TEST_CASE("the IRQ fields of both copies are ORed", "[merge]") {
    const auto sent = frame_of({{wire::Command::Brd, 0, {0, 0}}});
    SECTION("broken ring: the RED half raised the DL status event") {
        const auto main = frame_of({{wire::Command::Brd, 0, {0, 0}, 2, 0x0000}});
        const auto red = frame_of({{wire::Command::Brd, 0, {0, 0}, 3, 0x0004}});
        CHECK(merge(sent, {main, CopyPath::BouncedMain}, {red, CopyPath::BouncedRed}).datagrams[0].irq == 0x0004);
    }
    SECTION("broken ring: both halves raised something") {
        const auto main = frame_of({{wire::Command::Brd, 0, {0, 0}, 2, 0x0001}});
        const auto red = frame_of({{wire::Command::Brd, 0, {0, 0}, 3, 0x0004}});
        CHECK(merge(sent, {main, CopyPath::BouncedMain}, {red, CopyPath::BouncedRed}).datagrams[0].irq == 0x0005);
    }
    SECTION("closed ring: the processed copy's IRQ stays") {
        const auto main = frame_of({{wire::Command::Brd, 0, {0, 0}, 5, 0x0004}});
        const auto red = frame_of({{wire::Command::Brd, 0, {0, 0}, 0, 0x0000}});
        const auto m = merge(sent, {main, CopyPath::ThroughRing}, {red, CopyPath::Unprocessed});
        CHECK(m.datagrams[0].irq == 0x0004);
        CHECK(m.datagrams[0].wkc == 5);
    }
}

TEST_CASE("one copy lost on a broken ring: the result is partial", "[merge]") {
    const auto main = lrd_brd({0x12, 0x00}, 2, {0x08, 0x00}, 2);
    const auto m = merge(lrd_brd_sent(), {main, CopyPath::BouncedMain}, {});
    CHECK_FALSE(m.result.complete);
    CHECK(m.result.ring_broken);
    CHECK(m.datagrams[0].wkc == 2);

    const auto red = lrd_brd({0x00, 0x34}, 3, {0x08, 0x00}, 3);
    const auto r = merge(lrd_brd_sent(), {}, {red, CopyPath::BouncedRed});
    CHECK_FALSE(r.result.complete);
    CHECK(r.datagrams[0].data == Data{0x00, 0x34});
}

TEST_CASE("only the unprocessed RED copy back: nothing was processed", "[merge]") {
    const auto red = lrd_brd({0x00, 0x00}, 0, {0x00, 0x00}, 0);
    const auto m = merge(lrd_brd_sent(), {}, {red, CopyPath::Unprocessed});
    CHECK_FALSE(m.result.complete);
    CHECK_FALSE(m.result.ring_broken);
    CHECK(m.datagrams[0].wkc == 0);
}

TEST_CASE("no copy, or copies of different frames, cannot be merged", "[merge]") {
    Data out(wire::kMaxFrameSize);
    CHECK_FALSE(merge_copies(lrd_brd_sent(), {}, {}, out));

    const auto main = lrd_brd({0, 0}, 1, {0, 0}, 1);
    const auto single = frame_of({{wire::Command::Lrd, 0x01000000, {0, 0}}});
    auto r = merge_copies(lrd_brd_sent(), {main, CopyPath::BouncedMain}, {single, CopyPath::BouncedRed}, out);
    REQUIRE_FALSE(r);
    CHECK(r.error().message.find("differ") != std::string::npos);

    // A sent frame of another layout is refused too.
    auto s = merge_copies(single, {main, CopyPath::BouncedMain}, {main, CopyPath::BouncedRed}, out);
    REQUIRE_FALSE(s);
    CHECK(s.error().message.find("differ") != std::string::npos);
}
