#pragma once
// Acyclic datagrams (scan, InitCmds, state changes, mailbox) go through the
// cycle: a worker thread calls exchange() or exchange_all(), which queue the
// requests and wait (one wake-up however many requests); the cycle thread
// packs queued requests into a bounded number of frames per cycle, sends them
// with the cyclic frames, and completes them when their frame returns (or
// re-sends them until their deadline when it does not). The cycle thread
// never waits for a worker and never allocates.

#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::master {

class AcyclicQueue final : public bus::BusAccess {
public:
    static constexpr std::size_t kMaxBatches = 16;
    static constexpr std::size_t kMaxDatagramsPerFrame = 32;

    explicit AcyclicQueue(std::size_t max_frames_per_cycle);
    ~AcyclicQueue() override;

    // ---- any thread but the cycle thread
    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override;
    std::vector<Expected<bus::DatagramReply, bus::BusError>> exchange_all(
        std::span<const bus::DatagramRequest> requests) override;
    // From now on refuse new requests with `reason`, and fail the pending ones
    // with it (nullopt: accept again).
    void refuse(std::optional<bus::BusErrc> reason);
    std::optional<bus::BusErrc> refusal() const override;

    // ---- cycle thread
    std::size_t max_frames_per_cycle() const { return max_frames_per_cycle_; }
    // Packs pending requests into `builder` (as many as fit); the batch number
    // to complete later, or nullopt when nothing was pending or no batch is free.
    std::optional<std::uint16_t> fill_frame(wire::FrameBuilder& builder, link::Clock::time_point now);
    // The merged return of a batch, or nullptr when no copy came back.
    void complete(std::uint16_t batch, const wire::ConstFrameView* returned, link::Clock::time_point now);
    // The retry index to put in the source MAC of a batch's frame (0 on a first attempt).
    std::uint8_t retry_index(std::uint16_t batch) const;
    // Fails every request in flight (the cycle thread has stopped for good).
    void fail_in_flight(bus::BusErrc reason);

    std::uint64_t resent() const { return resent_; }

private:
    struct Waiter;
    struct Pending;
    struct Batch {
        bool in_use = false;
        std::size_t count = 0;
        std::array<Pending*, kMaxDatagramsPerFrame> items{};
    };

    void finish(Pending& pending, std::optional<bus::BusError> error);

    const std::size_t max_frames_per_cycle_;
    mutable std::mutex mutex_;
    std::deque<Pending*> queue_;  // guarded by mutex_; nodes are owned by waiting callers
    std::optional<bus::BusErrc> refusal_;
    std::array<Batch, kMaxBatches> batches_{};  // cycle thread only
    std::uint64_t resent_ = 0;
};

}  // namespace ecpair::master
