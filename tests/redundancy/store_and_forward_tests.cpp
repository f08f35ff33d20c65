// StoreAndForward over in-memory cables: the INACTIVE's MAIN and RED links
// are MemoryLinks whose far ends the test drives. Forwarding bits in both
// directions, circulating-frame prevention, drops that are counted, the
// bounce when the way on is down or refuses, the hook and the stored
// callback, and both receive threads at once.

#include <catch2/catch.hpp>

#include <sys/eventfd.h>
#include <unistd.h>

#include <thread>

#include "ecpair/link/memory_link.hpp"
#include "ecpair/master/receive_thread.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

using namespace ecpair;
using ecpair::master::LinkRole;
using ecpair::redundancy::ForwardOutcome;
using ecpair::redundancy::StoreAndForward;

namespace {

using Frame = std::vector<std::uint8_t>;

wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x01, last}}; }

// An EtherCAT frame from the ACTIVE (NIC bytes 11:22:33) with source MAC byte 0 = byte0.
Frame ecat_frame(std::uint8_t byte0, std::uint8_t frame_id = 0x17) {
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    eth.source = wire::MacAddress{{byte0, frame_id, 0x00, 0x11, 0x22, 0x33}};
    wire::FrameBuilder builder(buffer, eth);
    wire::DatagramHeader lrd;
    lrd.command = wire::Command::Lrd;
    lrd.address = 0x00010000;
    const std::array<std::uint8_t, 4> data{1, 2, 3, 4};
    (void)builder.append(lrd, data);
    const Bytes frame = builder.finish();
    return {frame.begin(), frame.end()};
}

std::uint8_t byte0(const Frame& frame) { return frame[6]; }

// The frame with byte 0 of its source MAC replaced: what forwarding should have done.
Frame with_byte0(Frame frame, std::uint8_t value) {
    frame[6] = value;
    return frame;
}

// A NIC that refuses every send (a driver error).
class RefusingLink final : public link::Link {
public:
    RefusingLink() : fd_(eventfd(0, EFD_CLOEXEC)) {}
    ~RefusingLink() override { close(fd_); }
    const std::string& name() const override { return name_; }
    wire::MacAddress mac() const override { return ::mac(0x99); }
    Expected<void, link::LinkError> send(ConstBytes) override {
        ++attempts;
        return unexpected(link::LinkError{link::LinkErrc::SendFailed, "refusing: send failed"});
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> try_receive(Bytes) override {
        return std::optional<link::ReceivedFrame>{};
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> receive(Bytes, std::chrono::nanoseconds) override {
        return std::optional<link::ReceivedFrame>{};
    }
    int selectable_fd() const override { return fd_; }
    bool link_up() const override { return true; }

    int attempts = 0;

private:
    std::string name_ = "refusing";
    int fd_;
};

// The INACTIVE's two cables; the `far` ends are the neighbours (slaves on
// one side, the ACTIVE on the other).
struct Cables {
    link::MemoryWire::Ends main = link::MemoryWire::make_pair("inactive-main", mac(1), "far-main", mac(2),
                                                              link::MemoryWireOptions{256});
    link::MemoryWire::Ends red = link::MemoryWire::make_pair("inactive-red", mac(3), "far-red", mac(4),
                                                             link::MemoryWireOptions{256});

    link::MemoryLink& near(LinkRole role) { return role == LinkRole::Main ? *main.a : *red.a; }
    link::MemoryLink& far(LinkRole role) { return role == LinkRole::Main ? *main.b : *red.b; }

    // The neighbour on `role` sends the frame; the INACTIVE receives it and forwards it.
    ForwardOutcome deliver(StoreAndForward& saf, LinkRole role, const Frame& frame) {
        REQUIRE(far(role).send(frame));
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
        auto received = near(role).try_receive(buffer);
        REQUIRE(received);
        REQUIRE(received->has_value());
        return saf.on_frame(role, ConstBytes(buffer.data(), (*received)->size));
    }

    // What the neighbour on `role` received (nullopt: nothing).
    std::optional<Frame> taken(LinkRole role) {
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
        auto received = far(role).try_receive(buffer);
        REQUIRE(received);
        if (!received->has_value()) return std::nullopt;
        return Frame(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>((*received)->size));
    }
};

}  // namespace

TEST_CASE("frames cross to the other adapter with its forwarding bit", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));

    // From the slaves (ACTIVE's MAIN copy) on RED: out of MAIN, 0x02 | 0x04.
    const Frame from_slaves = ecat_frame(0x02);
    CHECK(cables.deliver(saf, LinkRole::Red, from_slaves) == ForwardOutcome::Forwarded);
    CHECK(cables.taken(LinkRole::Main) == with_byte0(from_slaves, 0x06));
    CHECK_FALSE(cables.taken(LinkRole::Red));

    // From the ACTIVE's RED on MAIN: out of RED, 0x08 | 0x80.
    const Frame from_active = ecat_frame(0x08);
    CHECK(cables.deliver(saf, LinkRole::Main, from_active) == ForwardOutcome::Forwarded);
    CHECK(cables.taken(LinkRole::Red) == with_byte0(from_active, 0x88));
    CHECK_FALSE(cables.taken(LinkRole::Main));

    const auto c = saf.counters();
    CHECK(c.forwarded_red_to_main == 1);
    CHECK(c.forwarded_main_to_red == 1);
    CHECK(c.bounced + c.dropped_circulating + c.dropped_damaged + c.dropped_non_ethercat + c.send_failures == 0);
}

TEST_CASE("a frame is forwarded at most once per adapter", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));

    // A frame that loops (RED -> MAIN -> back into RED) is not forwarded out of MAIN twice.
    CHECK(cables.deliver(saf, LinkRole::Red, ecat_frame(0x00)) == ForwardOutcome::Forwarded);
    const auto once = cables.taken(LinkRole::Main);
    REQUIRE(once);
    CHECK(byte0(*once) == 0x04);
    CHECK(cables.deliver(saf, LinkRole::Red, *once) == ForwardOutcome::DroppedCirculating);
    CHECK_FALSE(cables.taken(LinkRole::Main));

    // It may still leave once by RED, and then never again.
    CHECK(cables.deliver(saf, LinkRole::Main, *once) == ForwardOutcome::Forwarded);
    const auto twice = cables.taken(LinkRole::Red);
    REQUIRE(twice);
    CHECK(byte0(*twice) == 0x84);
    CHECK(cables.deliver(saf, LinkRole::Main, *twice) == ForwardOutcome::DroppedCirculating);
    CHECK(cables.deliver(saf, LinkRole::Red, *twice) == ForwardOutcome::DroppedCirculating);
    CHECK_FALSE(cables.taken(LinkRole::Main));
    CHECK_FALSE(cables.taken(LinkRole::Red));
    CHECK(saf.counters().dropped_circulating == 3);
}

TEST_CASE("non-EtherCAT and damaged frames are dropped and counted", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));

    Frame ipv4 = ecat_frame(0x00);
    ipv4[12] = 0x08;
    ipv4[13] = 0x00;
    CHECK(cables.deliver(saf, LinkRole::Main, ipv4) == ForwardOutcome::DroppedNonEtherCat);

    Frame overrun = ecat_frame(0x00);
    overrun[16 + 6] = 0xFF;  // the datagram's length runs past the frame
    overrun[16 + 7] = 0x07;
    CHECK(cables.deliver(saf, LinkRole::Red, overrun) == ForwardOutcome::DroppedDamaged);

    Frame runt(10, 0xFF);  // not even an Ethernet header
    CHECK(cables.deliver(saf, LinkRole::Main, runt) == ForwardOutcome::DroppedDamaged);

    const Frame giant(wire::kMaxFrameSizeVlan + 1, 0x00);
    CHECK(saf.on_frame(LinkRole::Main, giant) == ForwardOutcome::DroppedDamaged);

    CHECK_FALSE(cables.taken(LinkRole::Main));
    CHECK_FALSE(cables.taken(LinkRole::Red));
    const auto c = saf.counters();
    CHECK(c.dropped_non_ethercat == 1);
    CHECK(c.dropped_damaged == 3);
    CHECK(c.forwarded_main_to_red + c.forwarded_red_to_main == 0);
}

TEST_CASE("a frame goes back where it came from while the way on is down", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));

    // The master-master cable (on the INACTIVE's MAIN) is broken: frames from the slaves return to them.
    saf.set_link_state(LinkRole::Main, false);
    CHECK_FALSE(saf.link_state(LinkRole::Main));
    const Frame from_slaves = ecat_frame(0x02);
    CHECK(cables.deliver(saf, LinkRole::Red, from_slaves) == ForwardOutcome::Bounced);
    CHECK(cables.taken(LinkRole::Red) == with_byte0(from_slaves, 0x82));
    CHECK_FALSE(cables.taken(LinkRole::Main));
    // One that already left by RED is not sent out of RED again.
    CHECK(cables.deliver(saf, LinkRole::Red, ecat_frame(0x80)) == ForwardOutcome::DroppedCirculating);

    // The cable behind the last slave (on RED) is broken instead.
    saf.set_link_state(LinkRole::Main, true);
    saf.set_link_state(LinkRole::Red, false);
    const Frame from_active = ecat_frame(0x08);
    CHECK(cables.deliver(saf, LinkRole::Main, from_active) == ForwardOutcome::Bounced);
    CHECK(cables.taken(LinkRole::Main) == with_byte0(from_active, 0x0C));

    // Repaired: forwarding as usual.
    saf.set_link_state(LinkRole::Red, true);
    CHECK(cables.deliver(saf, LinkRole::Main, from_active) == ForwardOutcome::Forwarded);
    CHECK(cables.taken(LinkRole::Red) == with_byte0(from_active, 0x88));
    CHECK(saf.counters().bounced == 2);
}

TEST_CASE("a frame the onward adapter refuses is bounced with the right bit only", "[redundancy][saf]") {
    Cables cables;
    RefusingLink refusing_main;
    StoreAndForward saf(refusing_main, cables.near(LinkRole::Red));

    const Frame from_slaves = ecat_frame(0x02);
    CHECK(cables.deliver(saf, LinkRole::Red, from_slaves) == ForwardOutcome::Bounced);
    CHECK(refusing_main.attempts == 1);
    // 0x80 for leaving by RED; the 0x04 of the failed attempt is not left behind.
    CHECK(cables.taken(LinkRole::Red) == with_byte0(from_slaves, 0x82));
    CHECK(saf.counters().send_failures == 1);
    CHECK(saf.counters().bounced == 1);

    // Arriving on the refusing adapter's side with nowhere else to go: the send failure is reported.
    saf.set_link_state(LinkRole::Red, false);
    CHECK(saf.on_frame(LinkRole::Main, ecat_frame(0x08)) == ForwardOutcome::SendFailed);
    CHECK(saf.counters().send_failures == 2);
}

TEST_CASE("the hook processes the frame before it leaves and the callback sees it as forwarded", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));
    struct Call {
        LinkRole arrived_on;
        bool first_pass;
        Frame frame;
    };
    std::vector<Call> hooked;
    std::vector<Call> stored;
    saf.set_hook([&](LinkRole arrived_on, wire::FrameView& frame, bool first_pass) {
        hooked.push_back({arrived_on, first_pass, {}});
        (*frame.begin()).set_wkc(0x55);
    });
    saf.set_stored_callback([&](LinkRole arrived_on, ConstBytes frame, bool first_pass) {
        stored.push_back({arrived_on, first_pass, Frame(frame.begin(), frame.end())});
    });

    CHECK(cables.deliver(saf, LinkRole::Red, ecat_frame(0x02)) == ForwardOutcome::Forwarded);
    CHECK(cables.deliver(saf, LinkRole::Main, ecat_frame(0x08)) == ForwardOutcome::Forwarded);
    CHECK(cables.deliver(saf, LinkRole::Main, ecat_frame(0x06)) == ForwardOutcome::Forwarded);  // forwarded before
    CHECK(cables.deliver(saf, LinkRole::Red, ecat_frame(0x04)) == ForwardOutcome::DroppedCirculating);

    REQUIRE(hooked.size() == 3);
    REQUIRE(stored.size() == 3);
    const std::array<std::pair<LinkRole, bool>, 3> expected{
        {{LinkRole::Red, true}, {LinkRole::Main, true}, {LinkRole::Main, false}}};
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CHECK(hooked[i].arrived_on == expected[i].first);
        CHECK(hooked[i].first_pass == expected[i].second);
        CHECK(stored[i].arrived_on == expected[i].first);
        CHECK(stored[i].first_pass == expected[i].second);
    }
    // The callback got exactly what left, hook's change and forwarding bit included.
    const auto out_main = cables.taken(LinkRole::Main);
    REQUIRE(out_main);
    CHECK(stored[0].frame == *out_main);
    auto view = wire::ConstFrameView::parse(*out_main);
    CHECK((*view->begin()).wkc() == 0x55);
    CHECK(byte0(*out_main) == 0x06);
    CHECK(stored[1].frame == cables.taken(LinkRole::Red));
    CHECK(byte0(stored[2].frame) == 0x86);
}

TEST_CASE("both receive threads forward at once", "[redundancy][saf]") {
    Cables cables;
    StoreAndForward saf(cables.near(LinkRole::Main), cables.near(LinkRole::Red));
    master::ReceiveThread main_rx(
        cables.near(LinkRole::Main),
        [&](ConstBytes frame, link::Clock::time_point) { saf.on_frame(LinkRole::Main, frame); }, "saf-main");
    master::ReceiveThread red_rx(
        cables.near(LinkRole::Red),
        [&](ConstBytes frame, link::Clock::time_point) { saf.on_frame(LinkRole::Red, frame); }, "saf-red");
    main_rx.start();
    red_rx.start();

    constexpr int kFrames = 100;
    std::thread active([&] {
        for (int i = 0; i < kFrames; ++i) (void)cables.far(LinkRole::Main).send(ecat_frame(0x08, static_cast<std::uint8_t>(i)));
    });
    std::thread slaves([&] {
        for (int i = 0; i < kFrames; ++i) (void)cables.far(LinkRole::Red).send(ecat_frame(0x02, static_cast<std::uint8_t>(i)));
    });
    active.join();
    slaves.join();

    // Every frame arrives on the other side, in order, with its bits.
    for (LinkRole out : {LinkRole::Main, LinkRole::Red}) {
        for (int i = 0; i < kFrames; ++i) {
            std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
            auto received = cables.far(out).receive(buffer, std::chrono::seconds(10));
            REQUIRE(received);
            REQUIRE(received->has_value());
            CHECK(buffer[6] == (out == LinkRole::Main ? 0x06 : 0x88));
            CHECK(buffer[7] == i);
        }
    }
    main_rx.stop();
    red_rx.stop();
    CHECK(saf.counters().forwarded_main_to_red == kFrames);
    CHECK(saf.counters().forwarded_red_to_main == kFrames);
}
