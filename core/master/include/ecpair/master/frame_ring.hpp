#pragma once
// A single-producer single-consumer ring of whole frames: a receive thread
// pushes what its link delivers, the cycle thread pops at the start of the
// next cycle. Lock-free and allocation-free after construction; a full ring
// drops the newest frame and counts it.

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::master {

struct RingFrame {
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> bytes{};
    std::size_t size = 0;
    link::Clock::time_point received_at;

    ConstBytes frame() const { return ConstBytes(bytes.data(), size); }
};

class FrameRing {
public:
    explicit FrameRing(std::size_t capacity = 256) : slots_(capacity) {}

    // Producer: copies the frame in; false when the ring is full.
    bool push(ConstBytes frame, link::Clock::time_point received_at) {
        const auto tail = tail_.load(std::memory_order_relaxed);
        const auto next = (tail + 1) % slots_.size();
        if (next == head_.load(std::memory_order_acquire)) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            return false;
        }
        RingFrame& slot = slots_[tail];
        slot.size = std::min(frame.size(), slot.bytes.size());
        std::copy_n(frame.begin(), slot.size, slot.bytes.begin());
        slot.received_at = received_at;
        tail_.store(next, std::memory_order_release);
        return true;
    }

    // Consumer: calls `visit(const RingFrame&)` for every queued frame.
    template <class Visitor>
    std::size_t drain(Visitor&& visit) {
        std::size_t n = 0;
        auto head = head_.load(std::memory_order_relaxed);
        while (head != tail_.load(std::memory_order_acquire)) {
            visit(slots_[head]);
            head = (head + 1) % slots_.size();
            head_.store(head, std::memory_order_release);
            ++n;
        }
        return n;
    }

    std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

private:
    std::vector<RingFrame> slots_;
    std::atomic<std::size_t> head_{0};
    std::atomic<std::size_t> tail_{0};
    std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace ecpair::master
