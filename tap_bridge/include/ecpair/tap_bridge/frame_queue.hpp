#pragma once
// A bounded queue of Ethernet frames between threads (TAP reader -> cycle or
// receive thread, and back to the TAP writer). Every slot is allocated at
// construction; push and pop copy one frame under a lock held for that copy
// only, so neither side ever waits for the other for long. A full queue
// refuses the frame and counts it: the caller's drop, never a wait.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::tap_bridge {

class FrameQueue {
public:
    static constexpr std::size_t kMaxFrame = wire::kMaxFrameSizeVlan;

    explicit FrameQueue(std::size_t capacity);

    // False when the queue is full or the frame larger than kMaxFrame (counted in refused()).
    bool push(ConstBytes frame);

    // Pops frames from the head while take(frame) accepts them (it copies the
    // frame and returns true) and `max` frames have not been taken. A frame
    // take() refuses stays at the head. Returns the frames taken.
    template <class Take>
    std::size_t pop_while(Take&& take, std::size_t max = SIZE_MAX) {
        std::lock_guard lock(mutex_);
        std::size_t taken = 0;
        while (count_ > 0 && taken < max) {
            const Slot& slot = slots_[head_];
            if (!take(ConstBytes(slot.bytes.data(), slot.size))) break;
            bytes_ -= slot.size;
            head_ = (head_ + 1) % slots_.size();
            --count_;
            ++taken;
        }
        depth_.store(count_, std::memory_order_relaxed);
        return taken;
    }
    // Shows frames from the head to look(frame) while it accepts them and
    // `max` were not shown; nothing is taken. Returns the frames accepted.
    template <class Look>
    std::size_t peek_while(Look&& look, std::size_t max = SIZE_MAX) const {
        std::lock_guard lock(mutex_);
        std::size_t seen = 0;
        while (seen < count_ && seen < max) {
            const Slot& slot = slots_[(head_ + seen) % slots_.size()];
            if (!look(ConstBytes(slot.bytes.data(), slot.size))) break;
            ++seen;
        }
        return seen;
    }
    // Drops the head frame (one that fits nowhere); false when empty.
    bool drop_head();

    std::size_t capacity() const { return slots_.size(); }
    std::size_t depth() const { return depth_.load(std::memory_order_relaxed); }
    // Bytes of the queued frames (frames only, no framing).
    std::size_t bytes() const;
    std::uint64_t refused() const { return refused_.load(std::memory_order_relaxed); }

private:
    struct Slot {
        std::array<std::uint8_t, kMaxFrame> bytes{};
        std::size_t size = 0;
    };

    mutable std::mutex mutex_;
    std::vector<Slot> slots_;
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::size_t bytes_ = 0;
    std::atomic<std::size_t> depth_{0};
    std::atomic<std::uint64_t> refused_{0};
};

}  // namespace ecpair::tap_bridge
