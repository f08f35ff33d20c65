#pragma once
// After a hot takeover the new ACTIVE knows the topology at once from the
// mirrored slave state image; this checks it in the background with a real
// bus scan through the master's acyclic queue and reports the result as a
// TopologyVerified event (a = 1 when the bus shows exactly the slaves the
// image says are present, with the ENI's identities).

#include <memory>
#include <thread>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/events.hpp"
#include "ecpair/master/slave_state_image.hpp"

namespace ecpair::redundancy {

class TopologyVerifier {
public:
    TopologyVerifier(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, master::EventQueue& events)
        : eni_(std::move(eni)), bus_(bus), events_(events) {}
    ~TopologyVerifier();

    // Starts a scan against `expected` (a running one is waited for first).
    void verify(std::vector<master::SlaveStateEntry> expected);

private:
    void run(const std::vector<master::SlaveStateEntry>& expected);

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    master::EventQueue& events_;
    std::jthread thread_;
};

}  // namespace ecpair::redundancy
