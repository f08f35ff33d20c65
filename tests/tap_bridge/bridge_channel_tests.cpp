// BridgeChannel between an ACTIVE and an INACTIVE end, in memory: the
// ACTIVE's frames are copied as the pair's ring copies them (a MAIN and a RED
// copy, each passing the INACTIVE once on its first pass) and returned to
// the ACTIVE. Delivery once and in order, fill once, drops by reason, the
// flow status in virtual time. Then the kernel path: the INACTIVE's answers
// prepared ahead for a program that answers the polls (here a model of
// store_and_forward.bpf.c's rules; kernel_forwarding_tests.cpp runs the
// real program).

#include <algorithm>
#include <array>
#include <deque>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/tap_bridge/bridge_channel.hpp"
#include "ecpair/wire/frame.hpp"

using namespace ecpair::tap_bridge;
using ecpair::master::CopyPath;
using ecpair::master::LinkRole;
using ecpair::master::ReturnedCopy;
using Frame = std::vector<std::uint8_t>;

namespace {

// Virtual time for the flow status.
struct VirtualClock {
    std::chrono::steady_clock::time_point now{std::chrono::seconds(1000)};
    auto function() {
        return [this] { return now; };
    }
};

class RecordingSender final : public ecpair::master::FrameSender {
public:
    ecpair::Bytes buffer() override { return buffer_; }
    ecpair::wire::EthernetHeader ethernet() const override {
        ecpair::wire::EthernetHeader h;
        h.destination = ecpair::wire::MacAddress::broadcast();
        return h;
    }
    void send(std::uint16_t index, ecpair::Bytes frame) override {
        sent.emplace_back(index, Frame(frame.begin(), frame.end()));
    }
    std::vector<std::pair<std::uint16_t, Frame>> sent;

private:
    std::array<std::uint8_t, ecpair::wire::kMaxFrameSizeVlan> buffer_{};
};

Frame ethernet(std::uint32_t n, std::size_t size = 100) {
    Frame f(size, static_cast<std::uint8_t>(n));
    for (int i = 0; i < 4; ++i) f[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(n >> (8 * i));
    f[12] = 0x08;
    return f;
}

std::vector<Frame> drain(FrameQueue& queue) {
    std::vector<Frame> out;
    queue.pop_while([&](ecpair::ConstBytes f) {
        out.emplace_back(f.begin(), f.end());
        return true;
    });
    return out;
}

BridgeChannelOptions options(std::uint32_t session, VirtualClock& clock, std::size_t queue = 64) {
    BridgeChannelOptions o;
    o.session = session;
    o.queue_frames = queue;
    o.clock = clock.function();
    return o;
}

// The kernel program's rules for the TAP bridge's polls, in memory: a poll
// takes the answer its other copy took (same id and size), else the slot
// named next if it is ready, of the poll's size and not yet claimed.
class ProgramSlots final : public ecpair::redundancy::PreparedPollAnswers {
public:
    struct Slot {
        std::uint64_t claimed_by = 0;
        bool ready = false;
        Frame data;
    };
    std::array<Slot, 4> slot{};
    std::size_t next = 0;
    std::size_t publications = 0;

    std::size_t slots() const override { return slot.size(); }
    std::uint64_t claimed_by(std::size_t i) const override { return slot.at(i).claimed_by; }
    void publish(std::size_t i, ecpair::ConstBytes data) override {
        slot.at(i) = Slot{0, true, Frame(data.begin(), data.end())};
        next = i;
        ++publications;
    }
    void withdraw_all() override {
        for (auto& s : slot) s.ready = false;
    }

    // What the program does to a copy on its first pass.
    void answer(Frame& frame) {
        auto view = ecpair::wire::FrameView::parse(frame);
        REQUIRE(view);
        for (auto d : *view) {
            const auto data = d.data();
            if (!is_bridge_datagram(d) || data.size() < kBridgeHeaderSize ||
                data[3] != static_cast<std::uint8_t>(BridgeKind::Poll)) {
                continue;
            }
            const auto id = (std::uint64_t{ecpair::load_le<std::uint32_t>(data, 8)} << 32) |
                            ecpair::load_le<std::uint32_t>(data, 12);
            Slot* chosen = nullptr;
            for (auto& s : slot) {
                if (s.ready && s.claimed_by == id && s.data.size() == data.size()) chosen = &s;
            }
            Slot& n = slot[next];
            if (chosen == nullptr && n.ready && n.claimed_by == 0 && n.data.size() == data.size()) {
                n.claimed_by = id;
                chosen = &n;
            }
            if (chosen == nullptr) continue;
            std::copy(chosen->data.begin(), chosen->data.end(), data.begin());
            d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
        }
    }
};

// The ring between an ACTIVE and an INACTIVE end. Each copy passes the
// INACTIVE once, on its first pass (as StoreAndForward calls the seam), and
// comes back to the ACTIVE (as the controller's receive path and the next
// cycle call it).
struct Ring {
    VirtualClock clock;
    BridgeChannel a{options(0xAAAA0001, clock)};
    BridgeChannel b{options(0xBBBB0002, clock)};
    BridgeChannel* active = &a;
    BridgeChannel* inactive = &b;
    std::size_t budget = 4;
    bool lose_main = false;
    bool lose_red = false;
    bool red_first = false;
    // The INACTIVE on the kernel path: `program` answers the polls, the
    // channel sees each copy as it arrived and prepares the next answers.
    bool kernel = false;
    ProgramSlots program;

    Ring() {
        a.role_changed(true);
        b.role_changed(false);
    }

    void swap_roles() {
        std::swap(active, inactive);
        active->role_changed(true);
        inactive->role_changed(false);
    }

    // Frame through the INACTIVE as a copy arriving on `link`.
    void pass(Frame& copy, LinkRole link) {
        if (kernel) {
            const Frame arrived = copy;
            program.answer(copy);
            inactive->kernel_forwarded(link, arrived, program);
            return;
        }
        auto view = ecpair::wire::FrameView::parse(copy);
        REQUIRE(view);
        inactive->process(link, *view, true);
        inactive->forwarded(link, copy, true);
    }

    // One cycle: the ACTIVE sends, both copies pass the INACTIVE, the copies return.
    std::vector<std::pair<std::uint16_t, Frame>> cycle() {
        RecordingSender sender;
        if (kernel) inactive->prepare_answers(program);  // the INACTIVE's cycle
        active->send_frames(sender, 1, budget);
        for (auto& [index, frame] : sender.sent) {
            Frame main = frame;
            Frame red = frame;
            // The RED copy reaches the INACTIVE's MAIN straight over the
            // master-master cable, the MAIN copy its RED through the slaves.
            if (red_first) {
                if (!lose_red) pass(red, LinkRole::Main);
                if (!lose_main) pass(main, LinkRole::Red);
            } else {
                if (!lose_main) pass(main, LinkRole::Red);
                if (!lose_red) pass(red, LinkRole::Main);
            }
            // Back at the ACTIVE: the receive threads hand every frame over at once...
            if (!lose_main) active->returned(LinkRole::Red, main);
            if (!lose_red) active->returned(LinkRole::Main, red);
            // ...and next cycle the copies that came back in time.
            const ReturnedCopy main_copy{lose_main ? ecpair::ConstBytes{} : ecpair::ConstBytes(main),
                                         lose_main ? CopyPath::Missing : CopyPath::ThroughRing};
            const ReturnedCopy red_copy{lose_red ? ecpair::ConstBytes{} : ecpair::ConstBytes(red),
                                        lose_red ? CopyPath::Missing : CopyPath::Unprocessed};
            active->complete(index, main_copy, red_copy);
            frame = main;  // as it came back
        }
        return sender.sent;
    }
};

}  // namespace

TEST_CASE("the ACTIVE's frames reach the INACTIVE once and in order", "[tap_bridge]") {
    Ring ring;
    for (std::uint32_t n = 0; n < 20; ++n) ring.a.offer(ethernet(n, 60 + n * 50));
    for (int c = 0; c < 10; ++c) ring.cycle();
    const auto got = drain(ring.b.inbound());
    REQUIRE(got.size() == 20);
    for (std::uint32_t n = 0; n < 20; ++n) CHECK(got[n] == ethernet(n, 60 + n * 50));
    const auto b = ring.b.counters();
    CHECK(b.rx_frames == 20);
    CHECK(b.duplicates > 0);  // every DATA datagram came twice
    CHECK(b.dropped_lost == 0);
    CHECK(ring.a.counters().tx_frames == 20);
}

TEST_CASE("the INACTIVE's frames ride in polls: filled once, delivered once", "[tap_bridge]") {
    Ring ring;
    for (std::uint32_t n = 0; n < 30; ++n) ring.b.offer(ethernet(n, 400));
    std::size_t polls = 0;
    for (int c = 0; c < 10; ++c) {
        for (const auto& [index, frame] : ring.cycle()) {
            const auto view = ecpair::wire::ConstFrameView::parse(frame);
            REQUIRE(view);
            const auto d = decode_bridge_datagram((*view->begin()).data());
            REQUIRE(d);
            if (d->header.kind == BridgeKind::Answer) {
                ++polls;
                CHECK((*view->begin()).wkc() == 1);  // the INACTIVE wrote into it
            }
        }
    }
    const auto got = drain(ring.a.inbound());
    REQUIRE(got.size() == 30);
    for (std::uint32_t n = 0; n < 30; ++n) CHECK(got[n] == ethernet(n, 400));
    // Each poll was filled once although both copies passed: the second got the same answer.
    CHECK(ring.b.counters().answers_given == ring.a.counters().polls_sent);
    CHECK(ring.a.counters().polls_answered == ring.a.counters().polls_sent);
    CHECK(ring.a.counters().duplicates > 0);
    CHECK(ring.b.counters().tx_frames == 30);
    CHECK(polls > 0);
}

TEST_CASE("one copy lost or arriving first changes nothing - both lost counts as lost", "[tap_bridge]") {
    Ring ring;
    SECTION("MAIN copies lost") { ring.lose_main = true; }
    SECTION("RED copies lost") { ring.lose_red = true; }
    SECTION("RED copy first") { ring.red_first = true; }
    for (std::uint32_t n = 0; n < 8; ++n) {
        ring.a.offer(ethernet(n));
        ring.b.offer(ethernet(100 + n));
    }
    for (int c = 0; c < 6; ++c) ring.cycle();
    CHECK(drain(ring.b.inbound()).size() == 8);
    CHECK(drain(ring.a.inbound()).size() == 8);
    CHECK(ring.a.counters().dropped_lost == 0);
    CHECK(ring.b.counters().dropped_lost == 0);
}

TEST_CASE("a DATA datagram that never arrives is counted as lost, the next one delivered", "[tap_bridge]") {
    Ring ring;
    ring.budget = 1;
    for (std::uint32_t n = 1; n <= 3; ++n) ring.a.offer(ethernet(n, 1400));  // one datagram each
    ring.cycle();  // frame 1 arrives: the partner's sequence is known from here on
    ring.lose_main = ring.lose_red = true;
    ring.cycle();  // frame 2's datagram vanishes
    ring.lose_main = ring.lose_red = false;
    ring.cycle();
    const auto got = drain(ring.b.inbound());
    CHECK(got == std::vector<Frame>{ethernet(1, 1400), ethernet(3, 1400)});
    CHECK(ring.b.counters().dropped_lost == 1);
}

TEST_CASE("the bridge follows a role change both ways, without losses", "[tap_bridge]") {
    Ring ring;
    ring.a.offer(ethernet(1));
    ring.b.offer(ethernet(2));
    ring.cycle();
    ring.cycle();
    ring.swap_roles();  // b ACTIVE now: it sends, a answers
    ring.a.offer(ethernet(3));
    ring.b.offer(ethernet(4));
    ring.cycle();
    ring.cycle();
    const auto at_b = drain(ring.b.inbound());
    const auto at_a = drain(ring.a.inbound());
    CHECK(at_b == std::vector<Frame>{ethernet(1), ethernet(3)});
    CHECK(at_a == std::vector<Frame>{ethernet(2), ethernet(4)});
    CHECK(ring.a.counters().dropped_lost == 0);
    CHECK(ring.b.counters().dropped_lost == 0);
    CHECK(ring.a.counters().answers_given > 0);
    CHECK(ring.b.counters().polls_answered > 0);
}

TEST_CASE("a garbled answer is counted and never delivered", "[tap_bridge]") {
    Ring ring;
    ring.budget = 1;
    ring.b.offer(ethernet(7));
    RecordingSender sender;
    ring.a.send_frames(sender, 1, 1);
    REQUIRE(sender.sent.size() == 1);
    Frame copy = sender.sent[0].second;
    ring.pass(copy, LinkRole::Main);
    copy[60] ^= 0x40;  // a bit of the packed frame, after the INACTIVE filled it
    ring.a.returned(LinkRole::Red, copy);
    ring.a.complete(0, ReturnedCopy{copy, CopyPath::ThroughRing}, ReturnedCopy{});
    CHECK(ring.a.counters().dropped_garbled == 1);
    CHECK(ring.a.counters().polls_answered == 1);  // it came back filled, if garbled
    CHECK(ring.a.counters().rx_frames == 0);
    CHECK(ring.a.inbound_depth() == 0);
}

TEST_CASE("an answer that comes back after its cycle closed is still delivered", "[tap_bridge]") {
    Ring ring;
    ring.b.offer(ethernet(9));
    RecordingSender sender;
    ring.a.send_frames(sender, 1, 1);
    Frame copy = sender.sent[0].second;
    ring.pass(copy, LinkRole::Main);
    ring.a.complete(0, ReturnedCopy{}, ReturnedCopy{});  // the cycle closed without it
    ring.a.returned(LinkRole::Main, copy);                // then it arrived
    CHECK(drain(ring.a.inbound()) == std::vector<Frame>{ethernet(9)});
}

TEST_CASE("a poll nobody filled counts as unanswered", "[tap_bridge]") {
    Ring ring;
    RecordingSender sender;
    ring.a.send_frames(sender, 1, 2);
    REQUIRE(sender.sent.size() == 1);  // idle: one poll
    ring.a.complete(0, ReturnedCopy{sender.sent[0].second, CopyPath::ThroughRing}, ReturnedCopy{});
    CHECK(ring.a.counters().polls_unanswered == 1);
    CHECK(ring.a.counters().polls_answered == 0);
}

TEST_CASE("frames from the TAP that fit no datagram, or no queue, are dropped and counted", "[tap_bridge]") {
    VirtualClock clock;
    BridgeChannel c(options(1, clock, 4));
    c.offer(ethernet(1, largest_frame(kMaxBridgeDatagramData) + 1));
    c.offer(ethernet(1, 13));
    CHECK(c.counters().dropped_oversized == 2);
    for (std::uint32_t n = 0; n < 6; ++n) c.offer(ethernet(n));
    CHECK(c.outbound_depth() == 4);
    CHECK(c.counters().dropped_tx_queue_full == 2);
}

TEST_CASE("a frame too large for the partner's smaller polls is dropped, not stuck", "[tap_bridge]") {
    Ring ring;
    BridgeChannelOptions small = options(0xAAAA0009, ring.clock);
    small.poll_size = 200;
    BridgeChannel active(small);
    active.role_changed(true);
    ring.active = &active;
    ring.b.offer(ethernet(1, 1000));  // fits our datagram, not a 200-byte poll
    ring.b.offer(ethernet(2, 100));
    ring.cycle();
    ring.cycle();
    CHECK(ring.b.counters().dropped_oversized == 1);
    CHECK(drain(active.inbound()) == std::vector<Frame>{ethernet(2, 100)});
}

TEST_CASE("a full inbound queue drops and counts", "[tap_bridge]") {
    VirtualClock clock;
    Ring ring;
    BridgeChannel small(options(0xBBBB0003, clock, 2));
    small.role_changed(false);
    ring.inactive = &small;
    for (std::uint32_t n = 0; n < 5; ++n) ring.a.offer(ethernet(n));
    ring.cycle();
    CHECK(small.inbound_depth() == 2);
    CHECK(small.counters().dropped_rx_queue_full == 3);
}

TEST_CASE("a partner that restarts (new session) is delivered from its first datagram on", "[tap_bridge]") {
    Ring ring;
    ring.a.offer(ethernet(1));
    ring.cycle();
    BridgeChannel restarted(options(0xAAAA7777, ring.clock));
    restarted.role_changed(true);
    ring.active = &restarted;
    restarted.offer(ethernet(2));
    ring.cycle();
    CHECK(drain(ring.b.inbound()) == std::vector<Frame>{ethernet(1), ethernet(2)});
    CHECK(ring.b.counters().dropped_lost == 0);
}

TEST_CASE("the flow status says why nothing flows, in virtual time", "[tap_bridge]") {
    Ring ring;
    auto b = ring.b.flow();
    CHECK_FALSE(b.active);
    CHECK_FALSE(b.flowing);
    CHECK(b.why_not.find("no ACTIVE master polls the bridge") != std::string::npos);
    CHECK(ring.a.flow().why_not.find("no partner answers our polls") != std::string::npos);

    ring.cycle();
    CHECK(ring.a.flow().flowing);
    CHECK(ring.b.flow().flowing);
    CHECK(ring.b.flow().why_not.empty());

    ring.clock.now += BridgeChannel::kFlowTimeout + std::chrono::milliseconds(500);
    b = ring.b.flow();
    CHECK_FALSE(b.flowing);
    CHECK(b.why_not == "no poll from an ACTIVE master for 1.5 s");
    CHECK(ring.a.flow().why_not == "the partner stopped answering our polls 1.5 s ago");
}

TEST_CASE("frames of another writer in between do not make a partner's copies count twice", "[tap_bridge]") {
    Ring ring;
    ring.a.offer(ethernet(1));
    RecordingSender sender;
    ring.a.send_frames(sender, 1, 1);
    REQUIRE(sender.sent.size() == 1);
    Frame first = sender.sent[0].second;
    Frame second = first;
    ring.pass(first, LinkRole::Main);  // the RED copy: delivered
    // A DATA datagram of a stranger (session 0x5555) arrives between the copies.
    VirtualClock clock;
    BridgeChannel stranger(options(0x5555, clock));
    stranger.role_changed(true);
    stranger.offer(ethernet(2));
    RecordingSender other;
    stranger.send_frames(other, 1, 1);
    ring.pass(other.sent[0].second, LinkRole::Main);
    ring.pass(second, LinkRole::Red);  // the MAIN copy of the partner's datagram: a duplicate still
    CHECK(drain(ring.b.inbound()) == std::vector<Frame>{ethernet(1), ethernet(2)});
    CHECK(ring.b.counters().duplicates == 1);
}

// ---- the kernel path: answers prepared ahead

TEST_CASE("kernel path: the INACTIVE's frames ride in prepared answers, once and in order", "[tap_bridge]") {
    Ring ring;
    ring.kernel = true;
    SECTION("both copies") {}
    SECTION("MAIN copies lost") { ring.lose_main = true; }
    SECTION("RED copies lost") { ring.lose_red = true; }
    SECTION("RED copy first") { ring.red_first = true; }
    for (std::uint32_t n = 0; n < 30; ++n) ring.b.offer(ethernet(n, 400));
    for (std::uint32_t n = 0; n < 5; ++n) ring.a.offer(ethernet(100 + n));
    for (int c = 0; c < 12; ++c) ring.cycle();
    const auto got = drain(ring.a.inbound());
    REQUIRE(got.size() == 30);
    for (std::uint32_t n = 0; n < 30; ++n) CHECK(got[n] == ethernet(n, 400));
    CHECK(drain(ring.b.inbound()).size() == 5);  // the ACTIVE's DATA, delivered as the kernel forwards it
    const auto a = ring.a.counters();
    const auto b = ring.b.counters();
    CHECK(a.dropped_lost == 0);
    CHECK(a.dropped_garbled == 0);
    CHECK(b.tx_frames == 30);
    CHECK(ring.b.outbound_depth() == 0);
    // Every poll was answered (each once) but perhaps the first: its size was
    // not known before its first copy passed.
    CHECK(a.polls_unanswered <= 1);
    CHECK(a.polls_answered + a.polls_unanswered == a.polls_sent);
    CHECK(b.answers_given == a.polls_answered);
}

TEST_CASE("kernel path: frames stay queued until a poll takes their answer", "[tap_bridge]") {
    Ring ring;
    ring.kernel = true;
    ring.budget = 1;
    ring.cycle();  // the first poll: its size is known from now on, an empty answer waits
    const std::size_t before = ring.program.publications;
    REQUIRE(before > 0);
    ring.b.offer(ethernet(1));
    ring.b.prepare_answers(ring.program);  // the INACTIVE's cycle: the empty answer is replaced
    CHECK(ring.program.publications == before + 1);
    CHECK(ring.b.outbound_depth() == 1);  // packed into the answer, still queued
    ring.b.prepare_answers(ring.program);
    CHECK(ring.program.publications == before + 1);  // nothing changed: the answer waits as it is

    SECTION("a poll takes it: delivered, then off the queue") {
        ring.cycle();
        CHECK(drain(ring.a.inbound()) == std::vector<Frame>{ethernet(1)});
        CHECK(ring.b.outbound_depth() == 0);
        ring.cycle();
        CHECK(ring.a.counters().rx_frames == 1);  // the next answers are empty: nothing twice
    }
    SECTION("the role changes before a poll took it: it goes as DATA, once") {
        ring.swap_roles();  // b ACTIVE
        // a is the INACTIVE now: its first look withdraws every answer b prepared.
        ring.a.prepare_answers(ring.program);
        CHECK(std::none_of(ring.program.slot.begin(), ring.program.slot.end(), [](const auto& s) { return s.ready; }));
        ring.cycle();
        CHECK(drain(ring.a.inbound()) == std::vector<Frame>{ethernet(1)});
        CHECK(ring.a.counters().dropped_lost == 0);
        CHECK(ring.b.outbound_depth() == 0);
    }
}

TEST_CASE("kernel path: a poll of another size than the prepared answer is answered from the next one",
          "[tap_bridge]") {
    Ring ring;
    ring.kernel = true;
    ring.budget = 1;
    ring.b.offer(ethernet(1, 100));
    ring.lose_red = true;  // one copy: it passes before the answer is ready
    ring.cycle();          // size learnt: an answer of 1486 bytes with frame 1 waits
    ring.lose_red = false;
    BridgeChannelOptions small = options(0xAAAA0009, ring.clock);
    small.poll_size = 300;
    BridgeChannel active(small);
    active.role_changed(true);
    ring.active = &active;  // another ACTIVE, polling with 300 bytes
    ring.cycle();           // its first poll's first copy passes unanswered; the answer is prepared again for 300
    ring.cycle();
    ring.cycle();
    CHECK(drain(ring.a.inbound()).empty());
    CHECK(drain(active.inbound()) == std::vector<Frame>{ethernet(1, 100)});
    CHECK(active.counters().dropped_lost == 0);
    CHECK(ring.b.outbound_depth() == 0);
    CHECK(ring.b.counters().tx_frames == 1);
}
