// The frame paths allocate nothing once set up: CmfWriter::write on the
// cycle thread, and on the receive threads StoreAndForward::on_frame,
// process_as_inactive and CmfAssembler::feed. Counted by replacing the
// global operator new in this test binary (its own, so that no other test
// runs with the replacement).

#include <catch2/catch.hpp>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

#include "cmf_test_support.hpp"
#include "ecpair/link/memory_link.hpp"
#include "ecpair/redundancy/cyclic_master_red_frame.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"

namespace {

std::atomic<std::size_t> g_allocations{0};

void* counted_allocation(std::size_t size, std::size_t alignment = 0) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (size == 0) size = 1;
    if (alignment > alignof(std::max_align_t)) size = (size + alignment - 1) / alignment * alignment;
    return alignment > alignof(std::max_align_t) ? std::aligned_alloc(alignment, size) : std::malloc(size);
}

}  // namespace

// Every form of operator new and delete is replaced, so that memory from any
// of them is released by a matching one (sanitizers check that). Not inlined:
// GCC would otherwise see malloc/free where it expects new/delete and warn.
[[gnu::noinline]] void* operator new(std::size_t size) {
    if (void* p = counted_allocation(size)) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new[](std::size_t size) {
    if (void* p = counted_allocation(size)) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new(std::size_t size, std::align_val_t alignment) {
    if (void* p = counted_allocation(size, static_cast<std::size_t>(alignment))) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new[](std::size_t size, std::align_val_t alignment) {
    if (void* p = counted_allocation(size, static_cast<std::size_t>(alignment))) return p;
    throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    return counted_allocation(size);
}
[[gnu::noinline]] void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    return counted_allocation(size);
}
[[gnu::noinline]] void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return counted_allocation(size, static_cast<std::size_t>(alignment));
}
[[gnu::noinline]] void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return counted_allocation(size, static_cast<std::size_t>(alignment));
}
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

using namespace ecpair;
using namespace ecpair::redundancy;

namespace {

// Allocations made by f().
template <class F>
std::size_t allocations_in(F&& f) {
    const std::size_t before = g_allocations.load();
    f();
    return g_allocations.load() - before;
}

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
