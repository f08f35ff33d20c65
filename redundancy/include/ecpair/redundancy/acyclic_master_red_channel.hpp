#pragma once
// The seam through which master-to-master traffic (the TAP bridge, design.md
// §3 "Acyclic Master Red Frames") rides on the pair's frames, without
// redundancy/ knowing what the traffic is. The RedundancyController calls it:
//
//   ACTIVE, cycle thread:   send_frames() right after the CMF, with at most
//                           max_acyc_frames_per_cycle frames; complete() with
//                           the returned copies of each of them next cycle
//                           (indices are the channel's own, 0-based).
//   ACTIVE, receive threads: returned() with every frame that comes back, at
//                           once: what the partner wrote can be taken without
//                           waiting for the next cycle, and a copy that comes
//                           back after its cycle closed is not lost.
//   INACTIVE, receive threads (MAIN and RED may run at once):
//                           process() on every forwarded frame before it leaves
//                           (fill a poll in place), forwarded() after it left
//                           (deliver what it carried); first_pass is true when
//                           the frame came straight from the ACTIVE.
//   INACTIVE, kernel path:  the program forwards every frame and answers the
//                           polls from answers the channel prepared ahead
//                           (PreparedPollAnswers): kernel_forwarded() with
//                           each first-pass frame as it arrived (receive
//                           threads: deliver what it carried, see which
//                           answer its polls took), prepare_answers() once a
//                           cycle (cycle thread: frames queued since).
//   cycle thread:           role_changed() when the role takes effect (and
//                           once when the channel is attached).
//
// An implementation must not block or allocate in any of these.

#include <cstddef>
#include <cstdint>

#include "ecpair/common/bytes.hpp"
#include "ecpair/master/cycle_extension.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/master/redundant_merge.hpp"
#include "ecpair/redundancy/prepared_poll_answers.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::redundancy {

class AcyclicMasterRedChannel {
public:
    virtual ~AcyclicMasterRedChannel() = default;

    virtual void role_changed(bool active) = 0;

    virtual void send_frames(master::FrameSender& sender, std::uint64_t cycle, std::size_t max_frames) = 0;
    virtual void complete(std::uint16_t index, const master::ReturnedCopy& main_copy,
                          const master::ReturnedCopy& red_copy) = 0;
    virtual void returned(master::LinkRole arrived_on, ConstBytes frame) = 0;

    virtual void process(master::LinkRole arrived_on, wire::FrameView& frame, bool first_pass) = 0;
    virtual void forwarded(master::LinkRole arrived_on, ConstBytes frame, bool first_pass) = 0;

    virtual void kernel_forwarded(master::LinkRole arrived_on, ConstBytes frame, PreparedPollAnswers& answers) = 0;
    virtual void prepare_answers(PreparedPollAnswers& answers) = 0;
};

// FrameSender indices at and above this belong to the channel (the CMF's
// frames are numbered from 0, far below).
inline constexpr std::uint16_t kAcyclicChannelIndexBase = 0x8000;

}  // namespace ecpair::redundancy
