// The real clock: std::chrono::steady_clock, and sleeps that a stop request
// interrupts (a condition variable waiting on the stop token).

#include "ecpair/sequencer/clock.hpp"

#include <condition_variable>
#include <mutex>

namespace ecpair::sequencer {
namespace {

class SteadyClock final : public Clock {
public:
    time_point now() override { return std::chrono::steady_clock::now(); }

    void sleep_for(duration how_long, std::stop_token stop) override {
        std::mutex mutex;
        std::condition_variable_any wakeup;
        std::unique_lock lock(mutex);
        wakeup.wait_for(lock, stop, how_long, [] { return false; });
    }
};

}  // namespace

Clock& steady_clock() {
    static SteadyClock clock;
    return clock;
}

}  // namespace ecpair::sequencer
