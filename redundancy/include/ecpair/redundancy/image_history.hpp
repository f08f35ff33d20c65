#pragma once
// A record of the last N process images, by their checksums: for every cycle
// the ACTIVE's cycle counter, the CRC-32 of the inputs and of the outputs,
// and the master state. The ACTIVE records its image, the INACTIVE the image
// it mirrored under the ACTIVE's cycle number; comparing the two histories
// proves (or disproves) that the mirror equalled the image every cycle.
//
// Thread-safe: record() (cycle thread) and snapshot() (any thread) take a
// short lock; the checksums are computed before it is taken. The ring is
// allocated once.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::redundancy {

struct ImageRecord {
    std::uint64_t cycle = 0;  // the ACTIVE's cycle counter
    std::uint32_t inputs_crc = 0;
    std::uint32_t outputs_crc = 0;
    eni::SlaveState master_state = eni::SlaveState::Init;

    friend bool operator==(const ImageRecord&, const ImageRecord&) = default;
};

class ImageHistory {
public:
    static constexpr std::size_t kDefaultCapacity = 8192;

    // capacity 0 is taken as 1.
    explicit ImageHistory(std::size_t capacity = kDefaultCapacity);

    void record(const ImageRecord& entry);
    // Checksums the image and records it.
    void record(std::uint64_t cycle, ConstBytes inputs, ConstBytes outputs, eni::SlaveState master_state);

    // The records held, oldest first (at most capacity()).
    std::vector<ImageRecord> snapshot() const;
    std::size_t capacity() const { return ring_.size(); }

private:
    mutable std::mutex mutex_;
    std::vector<ImageRecord> ring_;
    std::size_t next_ = 0;   // where the next record goes
    std::size_t count_ = 0;  // records held
};

// How a mirror's history compares with the reference it should equal,
// cycle by cycle, over the cycles both hold.
struct HistoryComparison {
    std::size_t common_cycles = 0;  // cycles present in both
    std::size_t mismatches = 0;     // of those, records that differ
    std::optional<ImageRecord> first_reference_mismatch;  // the earliest differing pair, if any
    std::optional<ImageRecord> first_mirror_mismatch;
};
HistoryComparison compare_histories(std::span<const ImageRecord> reference, std::span<const ImageRecord> mirror);

}  // namespace ecpair::redundancy
