#include "ecpair/tap_bridge/frame_queue.hpp"

#include <algorithm>

namespace ecpair::tap_bridge {

FrameQueue::FrameQueue(std::size_t capacity) : slots_(std::max<std::size_t>(capacity, 1)) {}

bool FrameQueue::push(ConstBytes frame) {
    if (frame.size() > kMaxFrame) {
        refused_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    std::lock_guard lock(mutex_);
    if (count_ == slots_.size()) {
        refused_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    Slot& slot = slots_[(head_ + count_) % slots_.size()];
    std::copy(frame.begin(), frame.end(), slot.bytes.begin());
    slot.size = frame.size();
    bytes_ += frame.size();
    ++count_;
    depth_.store(count_, std::memory_order_relaxed);
    return true;
}

bool FrameQueue::drop_head() {
    std::lock_guard lock(mutex_);
    if (count_ == 0) return false;
    bytes_ -= slots_[head_].size;
    head_ = (head_ + 1) % slots_.size();
    --count_;
    depth_.store(count_, std::memory_order_relaxed);
    return true;
}

std::size_t FrameQueue::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

}  // namespace ecpair::tap_bridge
