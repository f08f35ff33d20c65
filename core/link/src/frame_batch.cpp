#include "ecpair/link/frame_batch.hpp"

#include <algorithm>

#include "ecpair/wire/constants.hpp"

namespace ecpair::link {
namespace {
constexpr std::size_t kSlotSize = wire::kMaxFrameSizeVlan;
}  // namespace

FrameBatch::FrameBatch(std::size_t capacity) : storage_(capacity * kSlotSize), frames_(capacity) {}

bool FrameBatch::append(ConstBytes frame) {
    if (full() || frame.size() > kSlotSize) return false;
    std::uint8_t* const slot = storage_.data() + count_ * kSlotSize;
    std::copy(frame.begin(), frame.end(), slot);
    frames_[count_++] = ConstBytes(slot, frame.size());
    return true;
}

}  // namespace ecpair::link
