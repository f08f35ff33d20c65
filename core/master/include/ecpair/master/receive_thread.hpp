#pragma once
// One receive thread per link ("interrupt mode", design.md §4): blocks in
// poll() on the link's fd and hands every frame to a handler at once. The
// handler runs on this thread: it must be quick (copy into a ring, or
// forward the frame in store-and-forward).

#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"

namespace ecpair::master {

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

private:
    void run();

    link::Link& link_;
    Handler handler_;
    std::string name_;
    int realtime_priority_;
    int stop_fd_ = -1;  // eventfd that wakes poll() for stop()
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> frames_{0};
    std::thread thread_;
};

}  // namespace ecpair::master
