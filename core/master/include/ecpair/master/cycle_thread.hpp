#pragma once
// The cycle thread (JobTask): wakes on an absolute deadline with
// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), so that jitter never
// accumulates, and runs the cycle body. It asks for SCHED_FIFO; when the
// system does not permit it, it says so once and runs anyway.
//
// With a phase reference (set before start) the deadlines follow another
// schedule (PhaseLock): a standby master runs in step with its partner.
//
// Timing is measured as it goes: how late each wake-up was (a histogram with
// 1 µs buckets), how many cycles started late, how many were skipped because
// the previous one overran. A stall (stall_cycles deadlines or more missed in
// a row: the machine did not run the thread, or a cycle overran) is also
// told as it happens, to a StallListener.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ecpair/link/link.hpp"
#include "ecpair/master/phase_lock.hpp"

namespace ecpair::master {

struct CycleThreadOptions {
    std::chrono::nanoseconds period{std::chrono::milliseconds(1)};
    int realtime_priority = 80;  // 0: do not ask for SCHED_FIFO
    // A cycle that wakes later than this after its deadline counts as late.
    std::chrono::nanoseconds late_threshold{0};  // 0: a quarter of the period
    std::string name = "ecpair-cycle";
    // This many deadlines missed in a row are a stall (StallListener).
    std::uint64_t stall_cycles = 4;
};

struct CycleTiming {
    std::uint64_t cycles = 0;
    std::uint64_t late = 0;
    std::uint64_t skipped = 0;  // deadlines missed entirely (overrun)
    std::chrono::nanoseconds max_wake_latency{0};
    bool realtime = false;
    // Wake-up latency percentile (0..100) from the histogram, in µs.
    double latency_percentile_us(double percentile) const;
    std::vector<std::uint64_t> histogram_us;  // [i] = wake-ups i..i+1 µs late; the last bucket collects the rest
};

class CycleThread {
public:
    using Body = std::function<void(link::Clock::time_point deadline)>;
    // A boundary of the schedule to follow, asked after every cycle; nullopt: run free.
    using PhaseReference = std::function<std::optional<link::Clock::time_point>()>;
    // On the cycle thread after a stall: how late the cycle woke, and the
    // deadlines it skipped (late wake-up and run together; it must not block).
    using StallListener = std::function<void(std::chrono::nanoseconds wake_latency, std::uint64_t missed)>;

    CycleThread(CycleThreadOptions options, Body body);
    ~CycleThread();
    CycleThread(const CycleThread&) = delete;
    CycleThread& operator=(const CycleThread&) = delete;

    void set_phase_reference(PhaseReference reference) { phase_reference_ = std::move(reference); }
    void set_stall_listener(StallListener listener) { stall_listener_ = std::move(listener); }  // before start()
    void start();
    void stop();  // waits for the running cycle to finish
    CycleTiming timing() const;

private:
    void run();

    CycleThreadOptions options_;
    Body body_;
    PhaseReference phase_reference_;
    StallListener stall_listener_;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    mutable std::mutex timing_mutex_;
    CycleTiming timing_;
};

}  // namespace ecpair::master
