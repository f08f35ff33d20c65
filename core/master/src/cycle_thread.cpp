#include "ecpair/master/cycle_thread.hpp"

#include <pthread.h>
#include <time.h>

#include <algorithm>
#include <cerrno>

#include "ecpair/common/realtime.hpp"

namespace ecpair::master {
namespace {

constexpr std::size_t kHistogramBuckets = 10'000;  // 0..10 ms in µs

timespec to_timespec(link::Clock::time_point t) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return ts;
}

}  // namespace

double CycleTiming::latency_percentile_us(double percentile) const {
    std::uint64_t total = 0;
    for (const auto n : histogram_us) total += n;
    if (total == 0) return 0.0;
    const auto target = static_cast<std::uint64_t>(static_cast<double>(total) * percentile / 100.0);
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < histogram_us.size(); ++i) {
        seen += histogram_us[i];
        if (seen > target) return static_cast<double>(i);
    }
    return static_cast<double>(histogram_us.size());
}

CycleThread::CycleThread(CycleThreadOptions options, Body body) : options_(std::move(options)), body_(std::move(body)) {
    if (options_.late_threshold.count() == 0) options_.late_threshold = options_.period / 4;
    timing_.histogram_us.assign(kHistogramBuckets, 0);
}

CycleThread::~CycleThread() { stop(); }

void CycleThread::start() {
    stop_ = false;
    thread_ = std::thread([this] { run(); });
}

void CycleThread::stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

CycleTiming CycleThread::timing() const {
    std::lock_guard lock(timing_mutex_);
    return timing_;
}

void CycleThread::run() {
    pthread_setname_np(pthread_self(), options_.name.substr(0, 15).c_str());
    const bool realtime = request_realtime(options_.realtime_priority, "cycle thread");
    {
        std::lock_guard lock(timing_mutex_);
        timing_.realtime = realtime;
    }
    const PhaseLock phase_lock(options_.period);
    auto deadline = link::Clock::now() + options_.period;
    while (!stop_.load(std::memory_order_relaxed)) {
        const auto ts = to_timespec(deadline);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
        }
        const auto woke = link::Clock::now();
        const auto latency = std::max(woke - deadline, link::Clock::duration::zero());
        body_(deadline);

        const auto us = static_cast<std::size_t>(std::chrono::duration_cast<std::chrono::microseconds>(latency).count());
        std::uint64_t skipped = 0;
        deadline += options_.period;
        if (phase_reference_) deadline = phase_lock.correct(deadline, phase_reference_());
        const auto finished = link::Clock::now();
        if (finished > deadline) {
            // Overran: resume at the next deadline still ahead instead of bursting.
            skipped = static_cast<std::uint64_t>((finished - deadline) / options_.period) + 1;
            deadline += options_.period * static_cast<std::int64_t>(skipped);
        }
        // The deadlines passed while it woke late or ran long: skipped.
        if (skipped >= options_.stall_cycles && stall_listener_) {
            stall_listener_(std::chrono::duration_cast<std::chrono::nanoseconds>(latency), skipped);
        }
        std::lock_guard lock(timing_mutex_);
        ++timing_.cycles;
        if (latency > options_.late_threshold) ++timing_.late;
        timing_.skipped += skipped;
        timing_.max_wake_latency = std::max(timing_.max_wake_latency,
                                            std::chrono::duration_cast<std::chrono::nanoseconds>(latency));
        ++timing_.histogram_us[std::min(us, kHistogramBuckets - 1)];
    }
}

}  // namespace ecpair::master
