#pragma once
// One direction of a MemoryWire: a bounded FIFO of frames in preallocated
// slots, plus an eventfd that is readable exactly while frames wait.

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "ecpair/link/link.hpp"
#include "unique_fd.hpp"

namespace ecpair::link::detail {

class FrameQueue {
public:
    // Throws std::invalid_argument for a zero capacity and std::system_error
    // when no eventfd can be created.
    explicit FrameQueue(std::size_t capacity);

    // Copies the frame in; false (and nothing queued) when the queue is full.
    // The frame must fit a slot (at most wire::kMaxFrameSizeVlan bytes).
    bool push(ConstBytes frame);

    // The oldest frame, copied into `buffer` (truncated when it does not fit).
    std::optional<ReceivedFrame> pop(Bytes buffer);

    int fd() const { return event_.get(); }

private:
    struct Slot {
        std::size_t size = 0;
        std::chrono::system_clock::time_point sent_at;
    };

    Bytes slot_bytes(std::size_t index);

    mutable std::mutex mutex_;
    std::vector<std::uint8_t> storage_;  // capacity slots of kMaxFrameSizeVlan bytes
    std::vector<Slot> slots_;
    std::size_t head_ = 0;   // index of the oldest frame
    std::size_t count_ = 0;  // frames waiting
    UniqueFd event_;         // counter is 1 while count_ > 0, else 0
};

}  // namespace ecpair::link::detail
