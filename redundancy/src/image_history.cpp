// ImageHistory: a fixed ring of records under a mutex; snapshot() unrolls it
// oldest first.

#include "ecpair/redundancy/image_history.hpp"

#include <algorithm>

#include "ecpair/common/crc32.hpp"

namespace ecpair::redundancy {

ImageHistory::ImageHistory(std::size_t capacity) : ring_(std::max<std::size_t>(capacity, 1)) {}

void ImageHistory::record(const ImageRecord& entry) {
    std::lock_guard lock(mutex_);
    ring_[next_] = entry;
    next_ = (next_ + 1) % ring_.size();
    count_ = std::min(count_ + 1, ring_.size());
}

void ImageHistory::record(std::uint64_t cycle, ConstBytes inputs, ConstBytes outputs, eni::SlaveState master_state,
                          bool mirrored) {
    record(ImageRecord{cycle, crc32(inputs), crc32(outputs), master_state, mirrored});
}

std::vector<ImageRecord> ImageHistory::snapshot() const {
    std::lock_guard lock(mutex_);
    std::vector<ImageRecord> records;
    records.reserve(count_);
    const std::size_t oldest = (next_ + ring_.size() - count_) % ring_.size();
    for (std::size_t i = 0; i < count_; ++i) records.push_back(ring_[(oldest + i) % ring_.size()]);
    return records;
}

}  // namespace ecpair::redundancy
