#include "ecpair/supervisor/comm_timeout.hpp"

#include <algorithm>

namespace ecpair::supervisor {

CommTimeout::CommTimeout(std::chrono::nanoseconds timeout, std::chrono::nanoseconds link_loss_confirm,
                         std::chrono::nanoseconds cycle_time)
    : timeout_(timeout), link_loss_confirm_(link_loss_confirm), cycle_time_(cycle_time) {}

void CommTimeout::reset(TimePoint now) {
    last_cycle_ = now;
    silence_ = std::chrono::nanoseconds(0);
    link_lost_.reset();
}

void CommTimeout::link_lost(TimePoint now) {
    cycle(now);
    if (!link_lost_) link_lost_ = silence_;
}

void CommTimeout::cycle(TimePoint now) {
    if (last_cycle_ && now > *last_cycle_) {
        silence_ += std::min<std::chrono::nanoseconds>(now - *last_cycle_, 2 * cycle_time_);
        longest_ = std::max(longest_, silence_);
    }
    last_cycle_ = now;
}

std::chrono::nanoseconds CommTimeout::limit() const {
    if (!link_lost_) return timeout_;
    return std::min(timeout_, *link_lost_ + link_loss_confirm_);
}

}  // namespace ecpair::supervisor
