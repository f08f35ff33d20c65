// The ring: `count_` frames start at `head_`; push writes at head_+count_.
// The eventfd is written when the queue turns non-empty and drained when it
// turns empty, both under the mutex, so its readability always matches the
// queue and a poll() on it never wakes for nothing (and never misses a frame).

#include "frame_queue.hpp"

#include <sys/eventfd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>
#include <system_error>

#include "ecpair/wire/constants.hpp"

namespace ecpair::link::detail {
namespace {

constexpr std::size_t kSlotSize = wire::kMaxFrameSizeVlan;

}  // namespace

FrameQueue::FrameQueue(std::size_t capacity)
    : storage_(capacity * kSlotSize), slots_(capacity), event_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
    if (capacity == 0) throw std::invalid_argument("a memory link queue needs room for at least one frame");
    if (!event_.valid()) throw std::system_error(errno, std::system_category(), "eventfd for a memory link");
}

Bytes FrameQueue::slot_bytes(std::size_t index) { return Bytes(storage_).subspan(index * kSlotSize, kSlotSize); }

bool FrameQueue::push(ConstBytes frame) {
    std::lock_guard lock(mutex_);
    if (count_ == slots_.size()) return false;
    const std::size_t index = (head_ + count_) % slots_.size();
    std::copy(frame.begin(), frame.end(), slot_bytes(index).begin());
    slots_[index] = Slot{frame.size(), std::chrono::system_clock::now()};
    if (count_++ == 0) {
        const std::uint64_t one = 1;
        [[maybe_unused]] const auto written = ::write(event_.get(), &one, sizeof(one));
    }
    return true;
}

std::optional<ReceivedFrame> FrameQueue::pop(Bytes buffer) {
    std::lock_guard lock(mutex_);
    if (count_ == 0) return std::nullopt;
    const Slot& slot = slots_[head_];
    const std::size_t size = std::min(slot.size, buffer.size());
    std::copy_n(slot_bytes(head_).begin(), size, buffer.begin());
    const ReceivedFrame frame{size, slot.size, Clock::now(), slot.sent_at};
    head_ = (head_ + 1) % slots_.size();
    if (--count_ == 0) {
        std::uint64_t drained = 0;
        [[maybe_unused]] const auto read = ::read(event_.get(), &drained, sizeof(drained));
    }
    return frame;
}

}  // namespace ecpair::link::detail
