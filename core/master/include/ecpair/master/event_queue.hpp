#pragma once
// The bounded multi-producer queue between the threads that raise events
// (the cycle, the workers, the supervisor, the link guard...) and the one
// that reports them (ecpaird's event pump: log and operator API). Producers
// never wait for the consumer: the lock is held to copy one event or count
// one; a full queue drops and counts.
//
// A kind that repeats every cycle or frame while a fault lasts (its
// RepeatPolicy names a subject) does not flood the queue or the log: its
// first event is queued, the next ones are only counted, and the consumer
// gets a summary at most once a second and an end when the fault stopped
// (RepeatSummariser). The counts add up: the first event, the summaries'
// and the end's counts make the end's total.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "ecpair/master/event.hpp"
#include "ecpair/master/event_report.hpp"
#include "ecpair/master/repeat_summariser.hpp"

namespace ecpair::master {

struct EventQueueOptions {
    std::size_t capacity = 1024;
    RepeatOptions repeats{};
    // The time repeats are measured in; steady_clock unless a test drives it.
    std::function<std::chrono::steady_clock::time_point()> clock;
};

class EventQueue {
public:
    EventQueue();
    explicit EventQueue(std::size_t capacity);
    explicit EventQueue(EventQueueOptions options);

    void push(const Event& event);
    // For producers outside the cycle thread (state machine, slave monitor,
    // topology verifier, mirror): stamps the time and the current cycle of
    // the attached counter (0 when none is attached).
    void raise(EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0, std::uint32_t d = 0);
    // The master's cycle counter; nullptr detaches it. The counter must
    // outlive the attachment.
    void attach_cycle_counter(const std::atomic<std::uint64_t>* counter);
    // Waits up to `timeout` for an event or a due summary; returns what is
    // queued, then the summaries and ends due now (possibly nothing).
    std::vector<EventReport> pop_all(std::chrono::milliseconds timeout);
    std::uint64_t dropped() const;

private:
    std::uint64_t current_cycle() const;

    std::function<std::chrono::steady_clock::time_point()> clock_;
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::vector<Event> ring_;
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint64_t dropped_ = 0;
    RepeatSummariser repeats_;
    std::atomic<const std::atomic<std::uint64_t>*> cycle_counter_{nullptr};
};

}  // namespace ecpair::master
