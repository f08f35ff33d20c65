#pragma once
// The INACTIVE's watchdog on its ACTIVE partner: how long no complete
// Cyclic Master Red Frame has arrived, and whether that is long enough to
// call the partner failed.
//
// Silence is counted in this master's own cycles: every cycle adds the time
// since the previous one, but never more than two periods. A machine that
// stalls (a VM pause, an overloaded host) stalls both masters of the pair;
// when it resumes, the standby must not find "50 ms without a CMF" and take
// over from a partner that was just as frozen as itself. A partner that
// really stopped, while this master ran on, is called failed after
// `timeout` of silence.
//
// A link of our own going down shortens the wait: if the partner's links
// went down (its link guard, a dead controller), one of ours loses carrier at
// once; if no CMF then arrives on the other link within `link_loss_confirm`,
// the partner is gone and waiting the full timeout would only starve the
// slaves. (A pulled master-master cable also takes one of our links down,
// but then the CMF still arrives on the other and nothing happens.)
//
// Pure: time comes in with every call.

#include <chrono>
#include <optional>

namespace ecpair::supervisor {

using TimePoint = std::chrono::steady_clock::time_point;

class CommTimeout {
public:
    CommTimeout(std::chrono::nanoseconds timeout, std::chrono::nanoseconds link_loss_confirm,
                std::chrono::nanoseconds cycle_time);

    // Starts over: silence 0 from `now`.
    void reset(TimePoint now);
    // A complete CMF arrived.
    void heard(TimePoint now) { reset(now); }
    // One of our links went down.
    void link_lost(TimePoint now);
    // At every cycle boundary.
    void cycle(TimePoint now);

    bool expired() const { return silence_ >= limit(); }
    std::chrono::nanoseconds silence() const { return silence_; }
    // The silence that counts as failure now.
    std::chrono::nanoseconds limit() const;
    bool shortened() const { return link_lost_.has_value(); }
    std::chrono::nanoseconds timeout() const { return timeout_; }
    // The longest silence counted so far (how close the partner came to being called failed).
    std::chrono::nanoseconds longest_silence() const { return longest_; }

private:
    std::chrono::nanoseconds timeout_;
    std::chrono::nanoseconds link_loss_confirm_;
    std::chrono::nanoseconds cycle_time_;
    std::optional<TimePoint> last_cycle_;
    std::chrono::nanoseconds silence_{0};
    std::chrono::nanoseconds longest_{0};
    std::optional<std::chrono::nanoseconds> link_lost_;  // the silence when a link went down
};

}  // namespace ecpair::supervisor
