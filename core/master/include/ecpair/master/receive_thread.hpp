#pragma once
// One receive thread per link ("interrupt mode", design.md §4): blocks in
// poll() on the link's fd and hands every frame to a handler at once. The
// handler runs on this thread: it must be quick (copy into a ring, or
// forward the frame in store-and-forward).
//
// A thread can be parked when nothing needs a reaction to every frame, and
// the link's frames are then read once a cycle by whoever owns the link
// (drain_link). Its mode is an explicit state machine:
//
//   READING  --pause()-->   PARKING   (any thread; returns at once)
//   PARKING  --the thread, at its next frame boundary-->  PARKED
//   PARKING, PARKED --resume()-->  READING
//
// Until parked() says so the thread may still hand over a frame, so the
// owner reads the link only once it is parked: the two never read at once.
// A parked thread sleeps on its wake-up eventfd only, not on the link.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <thread>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"

namespace ecpair::master {

enum class ReceiveMode : std::uint8_t { Reading, Parking, Parked };
std::string_view to_string(ReceiveMode mode);

class ReceiveThread {
public:
    using Handler = std::function<void(ConstBytes frame, link::Clock::time_point received_at)>;

    // realtime_priority > 0 asks for SCHED_FIFO (frames are handed over as they arrive).
    ReceiveThread(link::Link& link, Handler handler, std::string name, int realtime_priority = 0);
    ~ReceiveThread();
    ReceiveThread(const ReceiveThread&) = delete;
    ReceiveThread& operator=(const ReceiveThread&) = delete;

    void start();
    void stop();
    std::uint64_t frames() const { return frames_.load(); }

    // ---- any thread
    void pause();
    void resume();
    bool parked() const { return mode_.load(std::memory_order_acquire) == ReceiveMode::Parked; }
    ReceiveMode mode() const { return mode_.load(std::memory_order_acquire); }

private:
    void run();
    void wake();
    void change_mode(ReceiveMode from, ReceiveMode to);

    link::Link& link_;
    Handler handler_;
    std::string name_;
    int realtime_priority_;
    int wake_fd_ = -1;  // eventfd that wakes poll() for stop(), pause() and resume()
    std::atomic<bool> stop_{false};
    std::atomic<ReceiveMode> mode_{ReceiveMode::Reading};
    std::atomic<std::uint64_t> frames_{0};
    std::thread thread_;
};

}  // namespace ecpair::master
