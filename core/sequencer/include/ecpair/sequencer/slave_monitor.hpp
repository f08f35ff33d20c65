#pragma once
// Keeps the slave state image current while the master runs: every period
// it reads each configured slave's AL status and status code by its station
// address (an FPRD of 6 bytes at 0x0130) through the master's acyclic queue,
// all slaves' reads at once.
// WKC 0 means the slave is not there (absent); a change of presence or a
// new error flag is raised as an event. It only polls once the station
// addresses are assigned (the master is PREOP or higher), and stays quiet
// while the bus refuses (an INACTIVE master).

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/slave_state_image.hpp"

namespace ecpair::sequencer {

class SlaveMonitor {
public:
    // `report_presence`: raise SlavePresence on a change (off when Hot-Connect reports presence).
    SlaveMonitor(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, master::SlaveStateImage& image,
                 master::EventQueue* events, std::function<bool()> addresses_assigned,
                 std::chrono::milliseconds period = std::chrono::milliseconds(100), bool report_presence = true);
    ~SlaveMonitor();
    SlaveMonitor(const SlaveMonitor&) = delete;
    SlaveMonitor& operator=(const SlaveMonitor&) = delete;

    // Polls every slave once now (on the caller's thread); used by tests and at start.
    void poll_once();
    std::uint64_t rounds() const;

private:
    void run(std::stop_token stop);
    void raise(master::EventKind kind, std::uint32_t a, std::uint32_t b = 0, std::uint32_t c = 0);

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    master::SlaveStateImage& image_;
    master::EventQueue* events_;
    std::function<bool()> addresses_assigned_;
    std::chrono::milliseconds period_;
    bool report_presence_;
    mutable std::mutex mutex_;
    std::condition_variable_any wake_;
    std::uint64_t rounds_ = 0;
    std::jthread thread_;  // last
};

}  // namespace ecpair::sequencer
