#pragma once
// How a pair member takes its links' frames (issue 12). A receive thread per
// link hands every frame over at once only while this member forwards in
// user space (INACTIVE on the user path: a frame must leave by the other
// link as soon as it arrives). Otherwise nothing needs a reaction to each
// frame (the ACTIVE completes its frames at the next cycle; with the kernel
// path the kernel has forwarded them and user space only mirrors), so the
// threads are parked and the cycle thread reads both links once a cycle: a
// pair member wakes once a cycle, not once a frame.
//
// The mode follows the role at every cycle boundary (after_cycle). A link is
// read by the cycle only once its thread has parked (ReceiveThread), so the
// two never read a link at once, and no frame is handled twice or lost on
// the way: until then the thread hands frames over as before.

#include <array>
#include <memory>
#include <optional>

#include "ecpair/link/link.hpp"
#include "ecpair/master/link_drain.hpp"
#include "ecpair/master/receive_thread.hpp"
#include "ecpair/redundancy/redundancy_controller.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::redundancy {

class PairReception {
public:
    // realtime_priority: the receive threads' (just below the cycle's).
    PairReception(link::Link& main, link::Link& red, RedundancyController& controller, int realtime_priority);
    ~PairReception();
    PairReception(const PairReception&) = delete;
    PairReception& operator=(const PairReception&) = delete;

    void start();
    void stop();

    // ---- cycle thread
    // Before the cycle: what waits on each link whose receive thread is parked.
    void before_cycle();
    // After the cycle (the role may have changed in it): park the receive
    // threads or let them take every frame again.
    void after_cycle();

private:
    std::array<link::Link*, 2> links_;
    RedundancyController& controller_;
    std::array<master::FrameHandler, 2> handlers_;  // MAIN, RED: into the controller
    std::array<std::unique_ptr<master::ReceiveThread>, 2> threads_;
    std::optional<bool> per_frame_;  // what after_cycle last chose
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan + 64> buffer_{};
};

}  // namespace ecpair::redundancy
