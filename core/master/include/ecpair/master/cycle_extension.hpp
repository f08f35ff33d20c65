#pragma once
// The seam through which master redundancy adds its own frames to a cycle
// (Cyclic Master Red Frames) and receives their returns, without the master
// knowing anything about redundancy.

#include <cstdint>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/master/process_image.hpp"
#include "ecpair/master/redundant_merge.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::master {

// Given to an extension while the master sends: build a frame into buffer()
// (the Ethernet header is the master's to fill), then send() it on every
// link in use, with its own frame id.
class FrameSender {
public:
    virtual ~FrameSender() = default;
    virtual Bytes buffer() = 0;
    virtual wire::EthernetHeader ethernet() const = 0;
    // `frame` lies in buffer(); `index` comes back in CycleExtension::complete.
    virtual void send(std::uint16_t index, Bytes frame) = 0;
};

class CycleExtension {
public:
    virtual ~CycleExtension() = default;
    // Called every cycle, sending or not, after the returned frames were
    // completed and before the master applies state and sending requests and
    // runs the application hook: the place to change role at the cycle
    // boundary and, while passive, to bring in a mirrored image.
    // `cycle_start` is the deadline the cycle was scheduled for.
    virtual void begin_cycle(ProcessImage& image, std::uint64_t cycle, link::Clock::time_point cycle_start) = 0;
    // Called every cycle after the cyclic slave frames, while the master sends.
    virtual void send_frames(FrameSender& sender, std::uint64_t cycle) = 0;
    // The returned copies of a frame sent through FrameSender in the previous cycle.
    virtual void complete(std::uint16_t index, const ReturnedCopy& main_copy, const ReturnedCopy& red_copy) = 0;
    // A frame another master sent (its source MAC names neither of our NICs),
    // received while sending; on the cycle thread, before begin_cycle.
    virtual void foreign_frame(LinkRole arrived_on, ConstBytes frame) = 0;
};

}  // namespace ecpair::master
