// ImageHistory: a fixed ring of records under a mutex; snapshot() unrolls it
// oldest first. compare_histories() indexes the reference by cycle and walks
// the mirror (a test and diagnostics helper, not on the cycle path).

#include "ecpair/redundancy/image_history.hpp"

#include <algorithm>
#include <unordered_map>

#include "ecpair/common/crc32.hpp"

namespace ecpair::redundancy {

ImageHistory::ImageHistory(std::size_t capacity) : ring_(std::max<std::size_t>(capacity, 1)) {}

void ImageHistory::record(const ImageRecord& entry) {
    std::lock_guard lock(mutex_);
    ring_[next_] = entry;
    next_ = (next_ + 1) % ring_.size();
    count_ = std::min(count_ + 1, ring_.size());
}

void ImageHistory::record(std::uint64_t cycle, ConstBytes inputs, ConstBytes outputs, eni::SlaveState master_state) {
    record(ImageRecord{cycle, crc32(inputs), crc32(outputs), master_state});
}

std::vector<ImageRecord> ImageHistory::snapshot() const {
    std::lock_guard lock(mutex_);
    std::vector<ImageRecord> records;
    records.reserve(count_);
    const std::size_t oldest = (next_ + ring_.size() - count_) % ring_.size();
    for (std::size_t i = 0; i < count_; ++i) records.push_back(ring_[(oldest + i) % ring_.size()]);
    return records;
}

HistoryComparison compare_histories(std::span<const ImageRecord> reference, std::span<const ImageRecord> mirror) {
    std::unordered_map<std::uint64_t, const ImageRecord*> by_cycle;
    by_cycle.reserve(reference.size());
    for (const ImageRecord& r : reference) by_cycle[r.cycle] = &r;

    HistoryComparison result;
    for (const ImageRecord& m : mirror) {
        const auto found = by_cycle.find(m.cycle);
        if (found == by_cycle.end()) continue;
        ++result.common_cycles;
        if (*found->second == m) continue;
        if (result.mismatches++ == 0 || m.cycle < result.first_mirror_mismatch->cycle) {
            result.first_reference_mismatch = *found->second;
            result.first_mirror_mismatch = m;
        }
    }
    return result;
}

}  // namespace ecpair::redundancy
