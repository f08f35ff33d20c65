#pragma once
// After a hot takeover the new ACTIVE knows the topology at once from the
// mirrored slave state image; this checks it in the background with a real
// bus scan through the master's acyclic queue and reports the result as a
// TopologyVerified event (a = 1 when the bus shows exactly the slaves the
// image says are present, with the ENI's identities). Right after a
// takeover the ring may still be open (the failed partner's side is only
// closing its ports), so a scan that gets no answer is retried a few times
// before the verifier gives up and says so.

#include <chrono>
#include <memory>
#include <stop_token>
#include <thread>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/slave_state_image.hpp"

namespace ecpair::redundancy {

class TopologyVerifier {
public:
    static constexpr int kAttempts = 5;

    TopologyVerifier(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, master::EventQueue& events,
                     std::chrono::milliseconds retry_after = std::chrono::milliseconds(500))
        : eni_(std::move(eni)), bus_(bus), events_(events), retry_after_(retry_after) {}
    ~TopologyVerifier();

    // Starts a scan against `expected` (a running one is stopped first).
    void verify(std::vector<master::SlaveStateEntry> expected);

private:
    void run(const std::stop_token& stop, const std::vector<master::SlaveStateEntry>& expected);

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    master::EventQueue& events_;
    std::chrono::milliseconds retry_after_;
    std::jthread thread_;
};

}  // namespace ecpair::redundancy
