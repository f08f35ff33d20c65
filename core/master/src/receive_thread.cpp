#include "ecpair/master/receive_thread.hpp"

#include <poll.h>
#include <pthread.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "ecpair/common/log.hpp"
#include "ecpair/common/realtime.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::master {

std::string_view to_string(ReceiveMode mode) {
    switch (mode) {
        case ReceiveMode::Reading: return "READING";
        case ReceiveMode::Parking: return "PARKING";
        case ReceiveMode::Parked: return "PARKED";
    }
    return "?";
}

ReceiveThread::ReceiveThread(link::Link& link, Handler handler, std::string name, int realtime_priority)
    : link_(link),
      handler_(std::move(handler)),
      name_(std::move(name)),
      realtime_priority_(realtime_priority),
      wake_fd_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {}

ReceiveThread::~ReceiveThread() {
    stop();
    if (wake_fd_ >= 0) close(wake_fd_);
}

void ReceiveThread::start() {
    stop_ = false;
    thread_ = std::thread([this] { run(); });
}

void ReceiveThread::stop() {
    if (!thread_.joinable()) return;
    stop_ = true;
    wake();
    thread_.join();
}

void ReceiveThread::wake() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = write(wake_fd_, &one, sizeof one);
}

void ReceiveThread::change_mode(ReceiveMode from, ReceiveMode to) {
    ReceiveMode expected = from;
    if (mode_.compare_exchange_strong(expected, to, std::memory_order_acq_rel)) {
        logger("link")->debug("{}: receive thread {} -> {}", name_, to_string(from), to_string(to));
    }
}

void ReceiveThread::pause() {
    change_mode(ReceiveMode::Reading, ReceiveMode::Parking);
    wake();
}

void ReceiveThread::resume() {
    change_mode(ReceiveMode::Parking, ReceiveMode::Reading);
    change_mode(ReceiveMode::Parked, ReceiveMode::Reading);
    wake();
}

void ReceiveThread::run() {
    pthread_setname_np(pthread_self(), name_.substr(0, 15).c_str());
    request_realtime(realtime_priority_, name_);
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan + 64> buffer{};
    std::array<pollfd, 2> fds{pollfd{wake_fd_, POLLIN, 0}, pollfd{link_.selectable_fd(), POLLIN, 0}};
    while (!stop_.load()) {
        change_mode(ReceiveMode::Parking, ReceiveMode::Parked);
        const bool reading = mode_.load(std::memory_order_acquire) == ReceiveMode::Reading;
        const int ready = poll(fds.data(), reading ? 2 : 1, -1);
        if (ready < 0) {
            if (errno == EINTR) continue;
            logger("link")->error("{}: poll failed: {}", name_, std::strerror(errno));
            return;
        }
        if (fds[0].revents != 0) {
            std::uint64_t woken = 0;
            [[maybe_unused]] const auto n = read(wake_fd_, &woken, sizeof woken);
            continue;  // stop, or the mode changed
        }
        // Frame by frame, so that a pause() takes effect before the next one.
        while (mode_.load(std::memory_order_acquire) == ReceiveMode::Reading) {
            auto frame = link_.try_receive(buffer);
            if (!frame) {
                // A failing link (interface gone down) can stay readable: back
                // off instead of spinning, but still react to stop() and pause().
                logger("link")->debug("{}: {}", name_, frame.error().message);
                poll(fds.data(), 1, 10);
                break;
            }
            if (!frame->has_value()) break;
            frames_.fetch_add(1, std::memory_order_relaxed);
            handler_(ConstBytes(buffer.data(), (*frame)->size), (*frame)->timestamp);
        }
    }
}

}  // namespace ecpair::master
