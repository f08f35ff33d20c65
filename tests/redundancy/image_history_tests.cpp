// ImageHistory and the CRC-32 it records images by: known CRC vectors, the
// ring keeping the newest records oldest-first, concurrent record/snapshot.

#include <catch2/catch.hpp>

#include <atomic>
#include <string_view>
#include <thread>

#include "ecpair/common/crc32.hpp"
#include "ecpair/redundancy/image_history.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;

namespace {

ConstBytes bytes_of(std::string_view text) {
    return ConstBytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

ImageRecord record_for(std::uint64_t cycle) {
    return ImageRecord{cycle, static_cast<std::uint32_t>(cycle * 3), static_cast<std::uint32_t>(cycle * 5),
                       eni::SlaveState::Op};
}

}  // namespace

TEST_CASE("CRC-32 matches the IEEE check values", "[redundancy][crc32]") {
    CHECK(crc32(bytes_of("123456789")) == 0xCBF43926u);
    CHECK(crc32({}) == 0u);
    CHECK(crc32(bytes_of("The quick brown fox jumps over the lazy dog")) == 0x414FA339u);
    // Piecewise equals whole.
    CHECK(crc32(bytes_of("56789"), crc32(bytes_of("1234"))) == 0xCBF43926u);
}

TEST_CASE("the history keeps the newest records, oldest first", "[redundancy][history]") {
    ImageHistory history(4);
    CHECK(history.snapshot().empty());
    for (std::uint64_t cycle = 1; cycle <= 3; ++cycle) history.record(record_for(cycle));
    CHECK(history.snapshot() == std::vector<ImageRecord>{record_for(1), record_for(2), record_for(3)});
    for (std::uint64_t cycle = 4; cycle <= 10; ++cycle) history.record(record_for(cycle));
    CHECK(history.snapshot() ==
          std::vector<ImageRecord>{record_for(7), record_for(8), record_for(9), record_for(10)});
    CHECK(history.capacity() == 4);
    CHECK(ImageHistory(0).capacity() == 1);
    CHECK(ImageHistory().capacity() == ImageHistory::kDefaultCapacity);
}

TEST_CASE("recording an image stores the CRCs of its inputs and outputs", "[redundancy][history]") {
    ImageHistory history;
    history.record(42, bytes_of("123456789"), bytes_of("The quick brown fox jumps over the lazy dog"),
                   eni::SlaveState::Safeop, true);
    CHECK(history.snapshot() ==
          std::vector<ImageRecord>{{42, 0xCBF43926u, 0x414FA339u, eni::SlaveState::Safeop, true}});
}

TEST_CASE("snapshots taken while the cycle records are consistent", "[redundancy][history]") {
    ImageHistory history(64);
    constexpr std::uint64_t kCycles = 20000;
    std::atomic<bool> recording{true};
    std::thread cycle([&] {
        for (std::uint64_t c = 1; c <= kCycles; ++c) history.record(record_for(c));
        recording.store(false);
    });
    // Every snapshot holds consecutive, intact records.
    bool consistent = true;
    while (recording.load()) {
        const auto records = history.snapshot();
        for (std::size_t i = 0; i < records.size(); ++i) {
            consistent = consistent && records[i] == record_for(records[i].cycle) &&
                         (i == 0 || records[i].cycle == records[i - 1].cycle + 1);
        }
    }
    cycle.join();
    CHECK(consistent);
    CHECK(history.snapshot().front().cycle == kCycles - 63);
}
