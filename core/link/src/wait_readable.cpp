// ppoll() with nanosecond timeouts. A signal interrupting the wait restarts
// it with the time that is left, so callers see either readiness or their
// full timeout.

#include "wait_readable.hpp"

#include <poll.h>

#include <cerrno>
#include <system_error>

namespace ecpair::link::detail {

Expected<bool, std::string> wait_readable(int fd, std::chrono::nanoseconds timeout) {
    using std::chrono::steady_clock;
    const auto deadline = steady_clock::now() + timeout;
    while (true) {
        const auto left = std::max(std::chrono::nanoseconds::zero(), deadline - steady_clock::now());
        const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(left);
        const timespec wait{static_cast<time_t>(seconds.count()), static_cast<long>((left - seconds).count())};
        pollfd entry{fd, POLLIN, 0};
        const int ready = ::ppoll(&entry, 1, &wait, nullptr);
        if (ready > 0) return true;
        if (ready == 0) return false;
        if (errno != EINTR) return unexpected(std::system_category().message(errno));
    }
}

}  // namespace ecpair::link::detail
