#pragma once
// Frames waiting to leave by one link together (Link::send_batch): a fixed
// number of preallocated frame-sized slots, so that filling and sending a
// batch allocates nothing. Frames are copied in: the caller may reuse its
// buffer at once.
//
//   FrameBatch batch(64);
//   if (batch.full()) flush(batch);
//   batch.append(frame);
//   link.send_batch(batch.frames());
//   batch.clear();

#include <cstddef>
#include <span>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::link {

class FrameBatch {
public:
    // Room for `capacity` frames of up to wire::kMaxFrameSizeVlan bytes.
    explicit FrameBatch(std::size_t capacity);

    // Copies the frame into the next slot. False (nothing copied) when the
    // batch is full or the frame is larger than a slot.
    bool append(ConstBytes frame);

    std::span<const ConstBytes> frames() const { return std::span(frames_).first(count_); }
    std::size_t size() const { return count_; }
    std::size_t capacity() const { return frames_.size(); }
    bool empty() const { return count_ == 0; }
    bool full() const { return count_ == frames_.size(); }
    void clear() { count_ = 0; }

private:
    std::vector<std::uint8_t> storage_;  // capacity slots of kSlotSize bytes
    std::vector<ConstBytes> frames_;     // views of the filled slots, [0, count_)
    std::size_t count_ = 0;
};

}  // namespace ecpair::link
