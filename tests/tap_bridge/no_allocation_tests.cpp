// The bridge's frame paths allocate nothing once set up: the ACTIVE's
// send_frames, returned and complete (cycle and receive threads), the
// INACTIVE's process and forwarded (receive threads), and the queues
// between them and the TAP thread. Counted by replacing the global
// operator new in this test binary (allocation_counter.cpp).

#include <array>
#include <vector>

#include <catch2/catch.hpp>

#include "allocation_counter.hpp"
#include "ecpair/tap_bridge/bridge_channel.hpp"
#include "ecpair/wire/frame.hpp"

using namespace ecpair;
using namespace ecpair::tap_bridge;
using ecpair::test::allocations_in;

namespace {

// Keeps the frames of a cycle in storage made up front, as the master does.
class PreallocatedSender final : public master::FrameSender {
public:
    Bytes buffer() override { return buffer_; }
    wire::EthernetHeader ethernet() const override {
        wire::EthernetHeader h;
        h.destination = wire::MacAddress::broadcast();
        return h;
    }
    void send(std::uint16_t index, Bytes frame) override {
        std::copy(frame.begin(), frame.end(), frames_[index].begin());
        sizes_[index] = frame.size();
        count = std::max<std::size_t>(count, index + 1u);
    }
    Bytes frame(std::size_t i) { return Bytes(frames_[i].data(), sizes_[i]); }
    std::size_t count = 0;

private:
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer_{};
    std::array<std::array<std::uint8_t, wire::kMaxFrameSizeVlan>, 8> frames_{};
    std::array<std::size_t, 8> sizes_{};
};

}  // namespace

TEST_CASE("the allocation counter sees allocations", "[tap_bridge][alloc]") {
    CHECK(allocations_in([] { std::vector<int> v(10); }) == 1);
}

TEST_CASE("the bridge's frame paths allocate nothing", "[tap_bridge][alloc]") {
    BridgeChannelOptions options;
    options.queue_frames = 64;
    options.session = 1;
    BridgeChannel active(options);
    options.session = 2;
    BridgeChannel inactive(options);
    active.role_changed(true);
    inactive.role_changed(false);
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> red_copy{};
    std::vector<std::uint8_t> ethernet(600, 0x33);
    PreallocatedSender sender;
    std::size_t delivered = 0;

    const auto cycle = [&] {
        for (int i = 0; i < 3; ++i) {
            active.offer(ethernet);
            inactive.offer(ethernet);
        }
        sender.count = 0;
        active.send_frames(sender, 1, 4);
        for (std::size_t f = 0; f < sender.count; ++f) {
            const Bytes main_copy = sender.frame(f);
            std::copy(main_copy.begin(), main_copy.end(), red_copy.begin());
            const Bytes red(red_copy.data(), main_copy.size());
            for (const Bytes copy : {main_copy, red}) {
                auto view = wire::FrameView::parse(copy);
                REQUIRE(view);
                inactive.process(master::LinkRole::Main, *view, true);
                inactive.forwarded(master::LinkRole::Main, copy, true);
                active.returned(master::LinkRole::Red, copy);
            }
            active.complete(static_cast<std::uint16_t>(f), master::ReturnedCopy{main_copy, master::CopyPath::ThroughRing},
                            master::ReturnedCopy{red, master::CopyPath::Unprocessed});
        }
        for (auto* channel : {&active, &inactive}) {
            delivered += channel->inbound().pop_while([](ConstBytes) { return true; });
        }
    };
    for (int i = 0; i < 5; ++i) cycle();  // first use: nothing left to set up afterwards
    const std::size_t warm = delivered;
    CHECK(allocations_in([&] {
              for (int i = 0; i < 200; ++i) cycle();
          }) == 0);
    CHECK(delivered > warm + 1000);  // frames did flow both ways meanwhile
    CHECK(active.counters().dropped_garbled == 0);
}
