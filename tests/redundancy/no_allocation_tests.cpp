// The frame paths allocate nothing once set up: CmfWriter::write on the
// cycle thread, and on the receive threads StoreAndForward::on_frame,
// process_as_inactive and CmfAssembler::feed. Counted by the shared
// allocation counter (tests/support), which replaces the global operator new
// in this test binary (its own, so that no other test runs with it).

#include <catch2/catch.hpp>

#include <array>
#include <cstddef>
#include <vector>

#include "allocation_counter.hpp"
#include "cmf_test_support.hpp"
#include "ecpair/link/memory_link.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;

namespace {

using test::allocations_in;

// A FrameSender that keeps frames in storage made up front, as a master's does.
class PreallocatedSender final : public master::FrameSender {
public:
    explicit PreallocatedSender(std::size_t frames) : frames_(frames), sizes_(frames) {}
    Bytes buffer() override { return buffer_; }
    wire::EthernetHeader ethernet() const override {
        wire::EthernetHeader h;
        h.destination = wire::MacAddress::broadcast();
        return h;
    }
    void send(std::uint16_t index, Bytes frame) override {
        std::copy(frame.begin(), frame.end(), frames_[index].begin());
        sizes_[index] = frame.size();
    }
    Bytes frame(std::size_t i) { return Bytes(frames_[i].data(), sizes_[i]); }

private:
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer_{};
    std::vector<std::array<std::uint8_t, wire::kMaxFrameSizeVlan>> frames_;
    std::vector<std::size_t> sizes_;
};

}  // namespace

TEST_CASE("the allocation counter sees allocations", "[redundancy][alloc]") {
    CHECK(allocations_in([] { std::vector<int> v(10); }) == 1);
}

TEST_CASE("writing, processing and assembling a CMF allocate nothing", "[redundancy][cmf][alloc]") {
    const CmfLayout layout = test::large_layout();
    CmfWriter writer(test::plan_of(layout));
    CmfAssembler assembler(test::plan_of(layout));
    PreallocatedSender sender(writer.plan().frame_count());
    test::TestContent content(layout, 1);
    const std::vector<std::uint8_t> pd_in(layout.parameters.master_pd_in_size, 0x11);
    const std::vector<std::uint8_t> standby_status(CmfStandbyStatus::kSize, 0x21);

    std::size_t completed = 0;
    const auto cycle = [&] {
        REQUIRE(writer.write(content.content, sender));
        for (std::size_t f = 0; f < writer.plan().frame_count(); ++f) {
            auto view = wire::FrameView::parse(sender.frame(f));
            REQUIRE(view);
            REQUIRE(process_as_inactive(*view, pd_in, standby_status));
            for (auto datagram : *view) {
                const auto outcome = assembler.feed(datagram);
                REQUIRE(outcome);
                if (*outcome == CmfAssembler::Outcome::Completed) ++completed;
            }
        }
    };
    cycle();  // first use: nothing left to set up afterwards
    std::size_t allocations = 0;
    for (std::uint64_t c = 2; c < 6; ++c) {
        content.content.cycle = c;
        allocations += allocations_in(cycle);
    }
    CHECK(allocations == 0);
    CHECK(completed == 5);
}

TEST_CASE("store-and-forward allocates nothing per frame", "[redundancy][saf][alloc]") {
    auto main = link::MemoryWire::make_pair("inactive-main", {{0x02, 0, 0, 0, 0, 1}}, "far-main", {{0x02, 0, 0, 0, 0, 2}});
    auto red = link::MemoryWire::make_pair("inactive-red", {{0x02, 0, 0, 0, 0, 3}}, "far-red", {{0x02, 0, 0, 0, 0, 4}});
    StoreAndForward saf(*main.a, *red.a);
    std::size_t hooked = 0;
    std::size_t stored = 0;
    saf.set_hook([&](master::LinkRole, wire::FrameView&, bool) { ++hooked; });
    saf.set_stored_callback([&](master::LinkRole, ConstBytes, bool) { ++stored; });

    const auto frames = test::write_cmf(test::small_layout(), test::TestContent(test::small_layout(), 1).content);
    const std::vector<std::uint8_t>& frame = frames[0].bytes;
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> drain{};
    const auto pass = [&] {
        REQUIRE(saf.on_frame(master::LinkRole::Red, frame) == ForwardOutcome::Forwarded);
        REQUIRE(saf.on_frame(master::LinkRole::Main, frame) == ForwardOutcome::Forwarded);
        REQUIRE(main.b->try_receive(drain));
        REQUIRE(red.b->try_receive(drain));
    };
    pass();
    CHECK(allocations_in([&] {
              for (int i = 0; i < 10; ++i) pass();
          }) == 0);
    CHECK(hooked == 22);
    CHECK(stored == 22);
}
