#include "ecpair/redundancy/pair_reception.hpp"

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/master/link_drain.hpp"

namespace ecpair::redundancy {
namespace {

// Frames read from one link per cycle at most: the rest wait for the next.
constexpr std::size_t kMaxReadPerCycle = 1024;

master::LinkRole role_of(std::size_t i) { return i == 0 ? master::LinkRole::Main : master::LinkRole::Red; }

}  // namespace

PairReception::PairReception(link::Link& main, link::Link& red, RedundancyController& controller,
                             int realtime_priority)
    : links_{&main, &red}, controller_(controller) {
    for (std::size_t i = 0; i < threads_.size(); ++i) {
        const auto role = role_of(i);
        handlers_[i] = [this, role](ConstBytes frame, link::Clock::time_point at) {
            controller_.on_frame(role, frame, at);
        };
        threads_[i] = std::make_unique<master::ReceiveThread>(
            *links_[i], handlers_[i], fmt::format("ecpair-rx-{}", role == master::LinkRole::Main ? "main" : "red"),
            realtime_priority);
    }
}

PairReception::~PairReception() { stop(); }

void PairReception::start() {
    for (auto& t : threads_) t->start();
}

void PairReception::stop() {
    for (auto& t : threads_) t->stop();
}

void PairReception::before_cycle() {
    for (std::size_t i = 0; i < threads_.size(); ++i) {
        if (threads_[i]->parked()) master::drain_link(*links_[i], buffer_, kMaxReadPerCycle, handlers_[i]);
    }
}

void PairReception::after_cycle() {
    const bool per_frame = controller_.forwards_in_user_space();
    if (per_frame_ == per_frame) return;
    per_frame_ = per_frame;
    for (auto& t : threads_) per_frame ? t->resume() : t->pause();
    logger("redundancy")->info(per_frame ? "frames are taken as they arrive, by a receive thread per link (the INACTIVE "
                                           "forwards in user space)"
                                         : "MAIN and RED are read once a cycle by the cycle thread (nothing forwards "
                                           "in user space)");
}

}  // namespace ecpair::redundancy
