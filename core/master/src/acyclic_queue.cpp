// Each caller owns its Pending nodes (one per request) and sleeps on its
// Waiter until the last of them is finished; the queue only holds pointers.
// The cycle thread takes pointers out under the mutex (a few instructions),
// builds frames outside it, and on completion copies the reply into the
// buffer the caller pre-sized, so the cycle thread allocates nothing. A lost
// frame puts its requests back at the front of the queue until their
// deadline passes. Lock order: the queue's mutex, then a Waiter's.

#include "ecpair/master/acyclic_queue.hpp"

#include <algorithm>
#include <condition_variable>

#include <fmt/format.h>

namespace ecpair::master {

struct AcyclicQueue::Waiter {
    std::mutex mutex;
    std::condition_variable done_cv;
    std::size_t remaining = 0;  // guarded by mutex: requests not finished yet
};

struct AcyclicQueue::Pending {
    const bus::DatagramRequest* request = nullptr;  // the caller's, alive while it waits
    link::Clock::time_point deadline;
    std::uint8_t attempt = 0;
    std::uint8_t index = 0;  // datagram position in its current batch
    bus::DatagramReply reply;
    std::optional<bus::BusError> error;  // guarded by the waiter's mutex once queued
    Waiter* waiter = nullptr;
};

AcyclicQueue::AcyclicQueue(std::size_t max_frames_per_cycle) : max_frames_per_cycle_(max_frames_per_cycle) {}

AcyclicQueue::~AcyclicQueue() { refuse(bus::BusErrc::Cancelled); }

Expected<bus::DatagramReply, bus::BusError> AcyclicQueue::exchange(const bus::DatagramRequest& request) {
    return std::move(exchange_all(std::span(&request, 1)).front());
}

std::vector<Expected<bus::DatagramReply, bus::BusError>> AcyclicQueue::exchange_all(
    std::span<const bus::DatagramRequest> requests) {
    Waiter waiter;
    std::vector<Pending> pending(requests.size());
    const auto now = link::Clock::now();
    auto last_deadline = now;
    for (std::size_t i = 0; i < requests.size(); ++i) {
        Pending& p = pending[i];
        p.request = &requests[i];
        p.waiter = &waiter;
        if (p.request->data.size() > wire::kMaxDatagramData) {
            p.error = bus::BusError{bus::BusErrc::InvalidRequest,
                                    fmt::format("{} bytes do not fit in one datagram", p.request->data.size())};
            continue;
        }
        p.reply.data.assign(p.request->data.size(), 0);
        p.deadline = now + p.request->timeout * (p.request->retries + 1);
        last_deadline = std::max(last_deadline, p.deadline);
        ++waiter.remaining;
    }
    {
        std::lock_guard lock(mutex_);
        for (Pending& p : pending) {
            if (p.error) continue;  // too long for a datagram: never queued
            if (refusal_) {
                p.error = bus::BusError{*refusal_, std::string(bus::to_string(*refusal_))};
                --waiter.remaining;
            } else {
                queue_.push_back(&p);
            }
        }
    }
    std::unique_lock lock(waiter.mutex);
    // The cycle re-sends until the deadline and then fails the request; the
    // margin covers a cycle thread that stopped running altogether.
    if (!waiter.done_cv.wait_until(lock, last_deadline + std::chrono::seconds(1),
                                   [&waiter] { return waiter.remaining == 0; })) {
        lock.unlock();
        {
            std::lock_guard queue_lock(mutex_);
            // Those still queued (not in a batch) come out so nobody touches them later.
            for (Pending& p : pending) {
                const auto it = std::find(queue_.begin(), queue_.end(), &p);
                if (it == queue_.end()) continue;
                queue_.erase(it);
                finish(p, bus::BusError{bus::BusErrc::Timeout, "the cycle did not send the request"});
            }
        }
        lock.lock();
        waiter.done_cv.wait(lock, [&waiter] { return waiter.remaining == 0; });
    }
    std::vector<Expected<bus::DatagramReply, bus::BusError>> replies;
    replies.reserve(pending.size());
    for (Pending& p : pending) {
        if (p.error) {
            replies.emplace_back(unexpected(std::move(*p.error)));
        } else {
            replies.emplace_back(std::move(p.reply));
        }
    }
    return replies;
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

std::optional<bus::BusErrc> AcyclicQueue::refusal() const {
    std::lock_guard lock(mutex_);
    return refusal_;
}

void AcyclicQueue::finish(Pending& pending, std::optional<bus::BusError> error) {
    Waiter& waiter = *pending.waiter;
    std::lock_guard lock(waiter.mutex);
    pending.error = std::move(error);
    if (--waiter.remaining == 0) waiter.done_cv.notify_one();
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
                                                 wire::to_string(p->request->command), p->request->address,
                                                 p->attempt)});
            continue;
        }
        wire::DatagramHeader header;
        header.command = p->request->command;
        header.index = static_cast<std::uint8_t>(batch.count);
        header.address = p->request->address;
        if (!builder.append(header, p->request->data)) break;  // the next frame takes it
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
                                                     wire::to_string(p->request->command), p->request->address,
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
