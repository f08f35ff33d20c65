// Each caller owns its Pending on its own stack and sleeps on its condition
// variable; the queue only holds pointers. The cycle thread takes pointers
// out under the mutex (a few instructions), builds frames outside it, and on
// completion copies the reply into the buffer the caller pre-sized, so the
// cycle thread allocates nothing. A lost frame puts its requests back at the
// front of the queue until their deadline passes.

#include "ecpair/master/acyclic_queue.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecpair::master {

struct AcyclicQueue::Pending {
    bus::DatagramRequest request;
    link::Clock::time_point deadline;
    std::uint8_t attempt = 0;
    std::uint8_t index = 0;  // datagram position in its current batch
    bus::DatagramReply reply;
    std::optional<bus::BusError> error;
    bool done = false;
    std::mutex mutex;
    std::condition_variable done_cv;
};

AcyclicQueue::AcyclicQueue(std::size_t max_frames_per_cycle) : max_frames_per_cycle_(max_frames_per_cycle) {}

AcyclicQueue::~AcyclicQueue() { refuse(bus::BusErrc::Cancelled); }

Expected<bus::DatagramReply, bus::BusError> AcyclicQueue::exchange(const bus::DatagramRequest& request) {
    if (request.data.size() > wire::kMaxDatagramData) {
        return unexpected(bus::BusError{bus::BusErrc::InvalidRequest,
                                        fmt::format("{} bytes do not fit in one datagram", request.data.size())});
    }
    Pending pending;
    pending.request = request;
    pending.reply.data.assign(request.data.size(), 0);
    pending.deadline = link::Clock::now() + request.timeout * (request.retries + 1);
    {
        std::lock_guard lock(mutex_);
        if (refusal_) {
            return unexpected(bus::BusError{*refusal_, std::string(bus::to_string(*refusal_))});
        }
        queue_.push_back(&pending);
    }
    std::unique_lock lock(pending.mutex);
    // The cycle re-sends until the deadline and then fails the request; the
    // margin covers a cycle thread that stopped running altogether.
    const bool finished = pending.done_cv.wait_until(lock, pending.deadline + std::chrono::seconds(1),
                                                     [&pending] { return pending.done; });
    if (!finished) {
        lock.unlock();
        std::lock_guard queue_lock(mutex_);
        // Still queued (not in a batch): take it out so nobody touches it later.
        const auto it = std::find(queue_.begin(), queue_.end(), &pending);
        if (it != queue_.end()) {
            queue_.erase(it);
            return unexpected(bus::BusError{bus::BusErrc::Timeout, "the cycle did not send the request"});
        }
        std::unique_lock relock(pending.mutex);
        pending.done_cv.wait(relock, [&pending] { return pending.done; });
    }
    if (pending.error) return unexpected(*pending.error);
    return std::move(pending.reply);
}

void AcyclicQueue::refuse(std::optional<bus::BusErrc> reason) {
    std::deque<Pending*> cancelled;
    {
        std::lock_guard lock(mutex_);
        refusal_ = reason;
        if (reason) cancelled.swap(queue_);
    }
    for (Pending* p : cancelled) {
        finish(*p, bus::BusError{*reason, fmt::format("request cancelled: {}", bus::to_string(*reason))});
    }
}

void AcyclicQueue::finish(Pending& pending, std::optional<bus::BusError> error) {
    std::lock_guard lock(pending.mutex);
    pending.error = std::move(error);
    pending.done = true;
    pending.done_cv.notify_one();
}

std::optional<std::uint16_t> AcyclicQueue::fill_frame(wire::FrameBuilder& builder, link::Clock::time_point now) {
    const auto free_batch = std::find_if(batches_.begin(), batches_.end(), [](const Batch& b) { return !b.in_use; });
    if (free_batch == batches_.end()) return std::nullopt;
    Batch& batch = *free_batch;
    batch.count = 0;

    std::lock_guard lock(mutex_);
    while (!queue_.empty() && batch.count < kMaxDatagramsPerFrame) {
        Pending* p = queue_.front();
        if (now > p->deadline) {
            queue_.pop_front();
            finish(*p, bus::BusError{bus::BusErrc::Timeout,
                                     fmt::format("{} at 0x{:08x}: no reply within {} attempt(s)",
                                                 wire::to_string(p->request.command), p->request.address,
                                                 p->attempt)});
            continue;
        }
        wire::DatagramHeader header;
        header.command = p->request.command;
        header.index = static_cast<std::uint8_t>(batch.count);
        header.address = p->request.address;
        if (!builder.append(header, p->request.data)) break;  // the next frame takes it
        queue_.pop_front();
        p->index = static_cast<std::uint8_t>(batch.count);
        ++p->attempt;
        batch.items[batch.count++] = p;
    }
    if (batch.count == 0) return std::nullopt;
    batch.in_use = true;
    return static_cast<std::uint16_t>(free_batch - batches_.begin());
}

void AcyclicQueue::complete(std::uint16_t batch_number, const wire::ConstFrameView* returned,
                            link::Clock::time_point now) {
    Batch& batch = batches_[batch_number];
    batch.in_use = false;
    if (returned == nullptr || returned->datagram_count() != batch.count) {
        // Lost (or garbled): send again, oldest first, unless the deadline passed.
        std::lock_guard lock(mutex_);
        for (std::size_t i = batch.count; i-- > 0;) {
            Pending* p = batch.items[i];
            if (now > p->deadline) {
                finish(*p, bus::BusError{bus::BusErrc::Timeout,
                                         fmt::format("{} at 0x{:08x}: no reply after {} attempt(s)",
                                                     wire::to_string(p->request.command), p->request.address,
                                                     p->attempt)});
            } else {
                queue_.push_front(p);
                ++resent_;
            }
        }
        return;
    }
    std::size_t i = 0;
    for (const auto d : *returned) {
        Pending* p = batch.items[i++];
        std::copy_n(d.data().begin(), std::min(d.data().size(), p->reply.data.size()), p->reply.data.begin());
        p->reply.wkc = d.wkc();
        p->reply.irq = d.irq();
        finish(*p, std::nullopt);
    }
}

std::uint8_t AcyclicQueue::retry_index(std::uint16_t batch_number) const {
    const Batch& batch = batches_[batch_number];
    std::uint8_t attempts = 1;
    for (std::size_t i = 0; i < batch.count; ++i) attempts = std::max(attempts, batch.items[i]->attempt);
    return static_cast<std::uint8_t>(std::min(attempts - 1, 7));
}

void AcyclicQueue::fail_in_flight(bus::BusErrc reason) {
    for (Batch& batch : batches_) {
        if (!batch.in_use) continue;
        batch.in_use = false;
        for (std::size_t i = 0; i < batch.count; ++i) {
            finish(*batch.items[i], bus::BusError{reason, fmt::format("request cancelled: {}", bus::to_string(reason))});
        }
    }
}

}  // namespace ecpair::master
