#pragma once
// The INACTIVE's frame path (design.md §1, §2, §4): every EtherCAT frame that
// arrives on one adapter leaves at once by the other, so that the ring stays
// closed through the standby master. The receive thread of each link calls
// on_frame(); nothing waits for the cycle.
//
//   arrived on RED  -> leaves by MAIN with source MAC byte 0 | 0x04
//   arrived on MAIN -> leaves by RED  with source MAC byte 0 | 0x80
//
// Circulating-frame prevention: a frame that already carries the forwarding
// bit of the adapter it would leave by has been through here before; it is
// dropped, so every frame is forwarded at most once per adapter.
//
// Bounce: when the adapter a frame should leave by is down (set_link_state)
// or its send fails, the frame goes back out of the adapter it came in on,
// with that adapter's forwarding bit (dropped if it already carries it) - as
// an ESC closes its port loop. A break on the master-master cable or behind
// the last slave thus still returns every frame to the ACTIVE, on the NIC it
// was sent from, where the ACTIVE's merge sees the break.
//
// Non-EtherCAT frames and frames FrameView::parse rejects are dropped and
// counted. Before a frame is sent, the hook may process it in place (the
// CMF's process_as_inactive); after it was sent, the stored callback gets it
// as forwarded (the mirror parses it there). first_pass tells whether the
// frame arrived without either forwarding bit, i.e. straight from the ACTIVE.
//
// Threads: on_frame() for one arrival link is called by one thread at a time
// (that link's receive thread); the two links' threads may run at once.
// Each arrival link has its own frame buffer, sends on one link are
// serialised by a short lock, counters are atomics. Nothing is allocated per
// frame. Set the hook and the callback before frames flow.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::redundancy {

enum class ForwardOutcome : std::uint8_t {
    Forwarded,           // left by the other adapter
    Bounced,             // left by the adapter it came in on
    DroppedCirculating,  // it already carried the forwarding bit of the adapter it would leave by
    DroppedNonEtherCat,  // not EtherType 0x88A4
    DroppedDamaged,      // EtherCAT, but not a valid datagram frame (or larger than any frame)
    SendFailed,          // no adapter could send it
};

struct StoreAndForwardCounters {
    std::uint64_t forwarded_main_to_red = 0;  // arrived on MAIN, left by RED
    std::uint64_t forwarded_red_to_main = 0;  // arrived on RED, left by MAIN
    std::uint64_t bounced = 0;
    std::uint64_t dropped_circulating = 0;
    std::uint64_t dropped_non_ethercat = 0;
    std::uint64_t dropped_damaged = 0;
    std::uint64_t send_failures = 0;  // failed link sends (a bounce after a failure counts separately)
};

class StoreAndForward {
public:
    using Hook = std::function<void(master::LinkRole arrived_on, wire::FrameView& frame, bool first_pass)>;
    using StoredCallback = std::function<void(master::LinkRole arrived_on, ConstBytes frame, bool first_pass)>;

    // Both links must outlive this object. Their link state starts as the links report it.
    StoreAndForward(link::Link& main, link::Link& red);

    void set_hook(Hook hook) { hook_ = std::move(hook); }
    void set_stored_callback(StoredCallback callback) { stored_ = std::move(callback); }

    // A frame received on `arrived_on` (not changed: it is copied into that link's buffer).
    ForwardOutcome on_frame(master::LinkRole arrived_on, ConstBytes frame);

    // The link monitor's view: frames do not leave by an adapter that is down.
    void set_link_state(master::LinkRole role, bool up);
    bool link_state(master::LinkRole role) const { return link_up_[index(role)].load(); }

    StoreAndForwardCounters counters() const;

private:
    static std::uint8_t forwarding_bit(master::LinkRole leaving_by);

    // Sets the forwarding bit of `leaving_by` unless the frame carries it already.
    static bool mark(wire::FrameView& frame, master::LinkRole leaving_by);
    bool send(master::LinkRole role, ConstBytes frame);

    std::array<link::Link*, 2> links_;
    std::array<std::atomic<bool>, 2> link_up_{};
    std::array<std::mutex, 2> send_mutex_;
    std::array<std::array<std::uint8_t, wire::kMaxFrameSizeVlan>, 2> buffers_{};  // per arrival link
    Hook hook_;
    StoredCallback stored_;

    struct AtomicCounters {
        std::atomic<std::uint64_t> forwarded_main_to_red{0}, forwarded_red_to_main{0}, bounced{0},
            dropped_circulating{0}, dropped_non_ethercat{0}, dropped_damaged{0}, send_failures{0};
    } counters_;
};

}  // namespace ecpair::redundancy
