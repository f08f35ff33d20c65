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

ReceiveThread::ReceiveThread(link::Link& link, Handler handler, std::string name, int realtime_priority)
    : link_(link),
      handler_(std::move(handler)),
      name_(std::move(name)),
      realtime_priority_(realtime_priority),
      stop_fd_(eventfd(0, EFD_CLOEXEC)) {}

ReceiveThread::~ReceiveThread() {
    stop();
    if (stop_fd_ >= 0) close(stop_fd_);
}

void ReceiveThread::start() {
    stop_ = false;
    thread_ = std::thread([this] { run(); });
}

void ReceiveThread::stop() {
    if (!thread_.joinable()) return;
    stop_ = true;
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = write(stop_fd_, &one, sizeof one);
    thread_.join();
    std::uint64_t drained = 0;
    [[maybe_unused]] const auto m = read(stop_fd_, &drained, sizeof drained);
}

void ReceiveThread::run() {
    pthread_setname_np(pthread_self(), name_.substr(0, 15).c_str());
    request_realtime(realtime_priority_, name_);
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan + 64> buffer{};
    std::array<pollfd, 2> fds{pollfd{link_.selectable_fd(), POLLIN, 0}, pollfd{stop_fd_, POLLIN, 0}};
    while (!stop_.load()) {
        const int ready = poll(fds.data(), fds.size(), -1);
        if (ready < 0) {
            if (errno == EINTR) continue;
            logger("link")->error("{}: poll failed: {}", name_, std::strerror(errno));
            return;
        }
        if (fds[1].revents != 0) break;
        for (;;) {
            auto frame = link_.try_receive(buffer);
            if (!frame) {
                // A failing link (interface gone down) can stay readable: back
                // off instead of spinning, but still react to stop().
                logger("link")->debug("{}: {}", name_, frame.error().message);
                poll(&fds[1], 1, 10);
                break;
            }
            if (!frame->has_value()) break;
            frames_.fetch_add(1, std::memory_order_relaxed);
            handler_(ConstBytes(buffer.data(), (*frame)->size), (*frame)->timestamp);
        }
    }
}

}  // namespace ecpair::master
