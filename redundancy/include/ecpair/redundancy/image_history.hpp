#pragma once
// A record of the last N process images, by their checksums: for every cycle
// the ACTIVE's cycle counter, the CRC-32 of the inputs and of the outputs,
// the master state, and whether the record is the ACTIVE's own image or the
// INACTIVE's mirror of it (under the ACTIVE's cycle number). Comparing two
// members' histories (control/image_history_comparison.hpp) proves or
// disproves that the mirror equalled the image every cycle.
//
// Thread-safe: record() (cycle thread) and snapshot() (any thread) take a
// short lock; the checksums are computed before it is taken. The ring is
// allocated once.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::redundancy {

struct ImageRecord {
    std::uint64_t cycle = 0;  // the ACTIVE's cycle counter
    std::uint32_t inputs_crc = 0;
    std::uint32_t outputs_crc = 0;
    eni::SlaveState master_state = eni::SlaveState::Init;
    bool mirrored = false;  // the INACTIVE's mirror; false: the ACTIVE's own image

    friend bool operator==(const ImageRecord&, const ImageRecord&) = default;
};

class ImageHistory {
public:
    static constexpr std::size_t kDefaultCapacity = 8192;

    // capacity 0 is taken as 1.
    explicit ImageHistory(std::size_t capacity = kDefaultCapacity);

    void record(const ImageRecord& entry);
    // Checksums the image and records it.
    void record(std::uint64_t cycle, ConstBytes inputs, ConstBytes outputs, eni::SlaveState master_state,
                bool mirrored);

    // The records held, oldest first (at most capacity()).
    std::vector<ImageRecord> snapshot() const;
    std::size_t capacity() const { return ring_.size(); }

private:
    mutable std::mutex mutex_;
    std::vector<ImageRecord> ring_;
    std::size_t next_ = 0;   // where the next record goes
    std::size_t count_ = 0;  // records held
};

}  // namespace ecpair::redundancy
