// MemoryWire owns both directions' queues; each MemoryLink holds the wire
// (so the queues live as long as any end) and references to its inbound and
// outbound queue. Send: size check, cable check, push into the peer's
// inbound queue, count the outcome. Receive: pop from the own inbound queue;
// the blocking variant waits on the queue's eventfd.

#include "ecpair/link/memory_link.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/constants.hpp"
#include "frame_queue.hpp"
#include "memory_wire_watcher.hpp"
#include "wait_readable.hpp"

namespace ecpair::link {

// ---- MemoryWire --------------------------------------------------------------

MemoryWire::Ends MemoryWire::make_pair(std::string name_a, wire::MacAddress mac_a, std::string name_b,
                                       wire::MacAddress mac_b, const MemoryWireOptions& options) {
    std::shared_ptr<MemoryWire> wire_ptr(new MemoryWire(name_a, name_b, options));
    auto a = std::unique_ptr<MemoryLink>(
        new MemoryLink(wire_ptr, std::move(name_a), mac_a, *wire_ptr->b_to_a_, *wire_ptr->a_to_b_));
    auto b = std::unique_ptr<MemoryLink>(
        new MemoryLink(wire_ptr, std::move(name_b), mac_b, *wire_ptr->a_to_b_, *wire_ptr->b_to_a_));
    return Ends{std::move(wire_ptr), std::move(a), std::move(b)};
}

MemoryWire::MemoryWire(std::string name_a, std::string name_b, const MemoryWireOptions& options)
    : name_a_(std::move(name_a)),
      name_b_(std::move(name_b)),
      a_to_b_(std::make_unique<detail::FrameQueue>(options.queue_capacity)),
      b_to_a_(std::make_unique<detail::FrameQueue>(options.queue_capacity)) {}

MemoryWire::~MemoryWire() = default;

void MemoryWire::set_link_up(bool up) {
    std::lock_guard lock(watchers_mutex_);
    if (up_.exchange(up) == up) return;
    logger("link")->info("memory wire {} <-> {}: link {}", name_a_, name_b_, up ? "up" : "down");
    const auto now = Clock::now();
    for (auto* watcher : watchers_) {
        watcher->report(LinkStateChange{name_a_, up, now});
        watcher->report(LinkStateChange{name_b_, up, now});
    }
}

std::unique_ptr<LinkStateSource> MemoryWire::watch() {
    // The wire is always owned by a shared_ptr (make_pair); the ends hold one.
    auto watcher = std::make_unique<detail::MemoryWireWatcher>(shared_from_this());
    std::lock_guard lock(watchers_mutex_);
    watchers_.push_back(watcher.get());
    return watcher;
}

void MemoryWire::remove_watcher(detail::MemoryWireWatcher* watcher) {
    std::lock_guard lock(watchers_mutex_);
    watchers_.erase(std::remove(watchers_.begin(), watchers_.end(), watcher), watchers_.end());
}

// ---- MemoryLink --------------------------------------------------------------

MemoryLink::MemoryLink(std::shared_ptr<MemoryWire> shared_wire, std::string name, wire::MacAddress mac,
                       detail::FrameQueue& inbound, detail::FrameQueue& outbound)
    : wire_(std::move(shared_wire)), name_(std::move(name)), mac_(mac), inbound_(inbound), outbound_(outbound) {}

MemoryLink::~MemoryLink() = default;

Expected<void, LinkError> MemoryLink::send(ConstBytes frame) {
    if (frame.size() > wire::kMaxFrameSizeVlan) {
        return unexpected(LinkError{LinkErrc::FrameTooLarge,
                                    fmt::format("memory link '{}': frame of {} bytes is larger than {}", name_,
                                                frame.size(), wire::kMaxFrameSizeVlan)});
    }
    if (!wire_->link_up()) {
        dropped_link_down_.fetch_add(1, std::memory_order_relaxed);
    } else if (outbound_.push(frame)) {
        delivered_.fetch_add(1, std::memory_order_relaxed);
    } else {
        dropped_queue_full_.fetch_add(1, std::memory_order_relaxed);
    }
    return {};
}

BatchSendResult MemoryLink::send_batch(std::span<const ConstBytes> frames) {
    if (!frames.empty()) batches_.fetch_add(1, std::memory_order_relaxed);
    return Link::send_batch(frames);
}

Expected<std::optional<ReceivedFrame>, LinkError> MemoryLink::try_receive(Bytes buffer) {
    return inbound_.pop(buffer);
}

Expected<std::optional<ReceivedFrame>, LinkError> MemoryLink::receive(Bytes buffer, std::chrono::nanoseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
        if (auto frame = inbound_.pop(buffer)) return frame;
        const auto left = deadline - Clock::now();
        if (left <= Clock::duration::zero()) return std::optional<ReceivedFrame>();
        if (auto ready = detail::wait_readable(inbound_.fd(), left); !ready) {
            return unexpected(LinkError{LinkErrc::ReceiveFailed,
                                        fmt::format("memory link '{}': poll failed: {}", name_, ready.error())});
        }
    }
}

int MemoryLink::selectable_fd() const { return inbound_.fd(); }

bool MemoryLink::link_up() const { return wire_->link_up(); }

MemoryLink::Counters MemoryLink::counters() const {
    return Counters{delivered_.load(std::memory_order_relaxed), dropped_queue_full_.load(std::memory_order_relaxed),
                    dropped_link_down_.load(std::memory_order_relaxed), batches_.load(std::memory_order_relaxed)};
}

}  // namespace ecpair::link
