#pragma once
// Small fakes for the sequencer tests: a virtual clock whose sleeps only
// move time on, and a BusAccess answered by a function that also keeps
// every request it saw.

#include <atomic>
#include <functional>
#include <mutex>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::test {

class VirtualClock final : public sequencer::Clock {
public:
    time_point now() override { return time_point(std::chrono::nanoseconds(now_ns_.load())); }
    void sleep_for(duration how_long, std::stop_token) override {
        now_ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(how_long).count();
    }
    void advance(duration how_long) { sleep_for(how_long, {}); }

private:
    std::atomic<std::int64_t> now_ns_{1'000'000'000};
};

using BusReply = Expected<bus::DatagramReply, bus::BusError>;

class ScriptedBus final : public bus::BusAccess {
public:
    using Handler = std::function<BusReply(const bus::DatagramRequest&)>;
    explicit ScriptedBus(Handler handler) : handler_(std::move(handler)) {}

    BusReply exchange(const bus::DatagramRequest& request) override {
        std::lock_guard lock(mutex_);
        requests_.push_back(request);
        return handler_(request);
    }
    std::vector<bus::DatagramRequest> requests() const {
        std::lock_guard lock(mutex_);
        return requests_;
    }

private:
    Handler handler_;
    mutable std::mutex mutex_;
    std::vector<bus::DatagramRequest> requests_;
};

inline BusReply reply(std::vector<std::uint8_t> data, std::uint16_t wkc) {
    return bus::DatagramReply{std::move(data), wkc};
}

inline BusReply bus_error(bus::BusErrc code) {
    return unexpected(bus::BusError{code, std::string(bus::to_string(code))});
}

inline std::uint16_t adp_of(const bus::DatagramRequest& r) { return static_cast<std::uint16_t>(r.address & 0xFFFF); }
inline std::uint16_t ado_of(const bus::DatagramRequest& r) { return static_cast<std::uint16_t>(r.address >> 16); }

}  // namespace ecpair::test
