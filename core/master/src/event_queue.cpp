#include "ecpair/master/event_queue.hpp"

#include <algorithm>

namespace ecpair::master {

EventQueue::EventQueue() : EventQueue(EventQueueOptions{}) {}

EventQueue::EventQueue(std::size_t capacity) : EventQueue([capacity] {
    EventQueueOptions options;
    options.capacity = capacity;
    return options;
}()) {}

EventQueue::EventQueue(EventQueueOptions options)
    : clock_(options.clock ? std::move(options.clock) : [] { return std::chrono::steady_clock::now(); }),
      ring_(std::max<std::size_t>(options.capacity, 1)),
      repeats_(options.repeats) {}

std::uint64_t EventQueue::current_cycle() const {
    const auto* counter = cycle_counter_.load();
    return counter != nullptr ? counter->load() : 0;
}

void EventQueue::raise(EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    push(Event{kind, current_cycle(), std::chrono::system_clock::now(), a, b, c, d});
}

void EventQueue::attach_cycle_counter(const std::atomic<std::uint64_t>* counter) { cycle_counter_.store(counter); }

void EventQueue::push(const Event& event) {
    const auto now = clock_();
    {
        std::lock_guard lock(mutex_);
        if (!repeats_.offer(event, now)) return;  // counted for the kind's next summary
        if (count_ == ring_.size()) {
            ++dropped_;
            return;
        }
        ring_[(head_ + count_) % ring_.size()] = event;
        ++count_;
    }
    ready_.notify_one();
}

std::vector<EventReport> EventQueue::pop_all(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    auto wait = std::chrono::steady_clock::duration(timeout);
    if (const auto next = repeats_.next_due()) {
        wait = std::clamp<std::chrono::steady_clock::duration>(*next - clock_(), std::chrono::steady_clock::duration::zero(),
                                                               wait);
    }
    ready_.wait_for(lock, wait, [this] { return count_ > 0; });
    std::vector<EventReport> out;
    out.reserve(count_);
    while (count_ > 0) {
        EventReport& report = out.emplace_back();
        report.event = ring_[head_];
        report.start_cycle = report.first_cycle = report.last_cycle = report.event.cycle;
        head_ = (head_ + 1) % ring_.size();
        --count_;
    }
    repeats_.due(clock_(), current_cycle(), std::chrono::system_clock::now(), out);
    return out;
}

std::uint64_t EventQueue::dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
}

}  // namespace ecpair::master
