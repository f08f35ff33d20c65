// StoreAndForward: one frame, start to end, on the receive thread of the
// link it arrived on:
//
//   copy into the arrival link's buffer -> parse (drop non-EtherCAT/damaged)
//   -> pick the adapter: the other one if up, else back where it came from
//   -> set that adapter's forwarding bit (drop if already set) -> hook
//   -> send; if the other adapter refuses, restore the source MAC and bounce
//   -> count -> stored callback
//
// The forwarding bits live in source MAC byte 0 (design.md §2); SourceMac
// decodes and encodes that byte so that no bit positions are spelled here.

#include "ecpair/redundancy/store_and_forward.hpp"

#include <algorithm>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace ecpair::redundancy {

using master::LinkRole;

StoreAndForward::StoreAndForward(link::Link& main, link::Link& red) : links_{&main, &red} {
    link_up_[index(LinkRole::Main)].store(main.link_up());
    link_up_[index(LinkRole::Red)].store(red.link_up());
}

void StoreAndForward::set_link_state(LinkRole role, bool up) {
    if (link_up_[index(role)].exchange(up) == up) return;
    if (up) {
        logger("redundancy")->info("store-and-forward: {} is up: frames from {} leave by {} again", to_string(role),
                                   to_string(other(role)), to_string(role));
    } else {
        logger("redundancy")->warn("store-and-forward: {} is down: frames from {} go back out of {}", to_string(role),
                                   to_string(other(role)), to_string(other(role)));
    }
}

StoreAndForwardCounters StoreAndForward::counters() const {
    return StoreAndForwardCounters{counters_.forwarded_main_to_red.load(), counters_.forwarded_red_to_main.load(),
                                   counters_.bounced.load(),               counters_.dropped_circulating.load(),
                                   counters_.dropped_non_ethercat.load(),  counters_.dropped_damaged.load(),
                                   counters_.send_failures.load()};
}

bool StoreAndForward::mark(wire::FrameView& frame, LinkRole leaving_by) {
    auto source = wire::SourceMac::decode(frame.ethernet().source);
    bool& bit = leaving_by == LinkRole::Main ? source.forwarded_main : source.forwarded_red;
    if (bit) return false;
    bit = true;
    frame.set_source(source.encode());
    return true;
}

bool StoreAndForward::send(LinkRole role, ConstBytes frame) {
    std::lock_guard lock(send_mutex_[index(role)]);
    auto sent = links_[index(role)]->send(frame);
    if (sent) return true;
    counters_.send_failures.fetch_add(1);
    logger("redundancy")->debug("store-and-forward: send on {} failed: {}", to_string(role), sent.error().message);
    return false;
}

ForwardOutcome StoreAndForward::on_frame(LinkRole arrived_on, ConstBytes received) {
    auto& buffer = buffers_[index(arrived_on)];
    if (received.size() > buffer.size()) {
        counters_.dropped_damaged.fetch_add(1);
        return ForwardOutcome::DroppedDamaged;
    }
    std::copy(received.begin(), received.end(), buffer.begin());
    const Bytes bytes(buffer.data(), received.size());

    auto parsed = wire::FrameView::parse(bytes);
    if (!parsed) {
        if (parsed.error().code == wire::DecodeErrc::NotEtherCat) {
            counters_.dropped_non_ethercat.fetch_add(1);
            return ForwardOutcome::DroppedNonEtherCat;
        }
        counters_.dropped_damaged.fetch_add(1);
        logger("redundancy")->debug("store-and-forward: frame from {} dropped: {}", to_string(arrived_on),
                                    parsed.error().describe());
        return ForwardOutcome::DroppedDamaged;
    }
    wire::FrameView& frame = *parsed;
    const wire::MacAddress arrived_source = frame.ethernet().source;
    const auto source = wire::SourceMac::decode(arrived_source);
    const bool first_pass = !source.forwarded_main && !source.forwarded_red;

    const LinkRole onward = other(arrived_on);
    LinkRole leaving_by = link_state(onward) ? onward : arrived_on;
    if (!mark(frame, leaving_by)) {
        counters_.dropped_circulating.fetch_add(1);
        return ForwardOutcome::DroppedCirculating;
    }
    if (hook_) hook_(arrived_on, frame, first_pass);
    if (!send(leaving_by, bytes)) {
        if (leaving_by == arrived_on) return ForwardOutcome::SendFailed;
        // The onward adapter refused the frame: close the loop here instead.
        leaving_by = arrived_on;
        frame.set_source(arrived_source);
        if (!mark(frame, leaving_by)) {
            counters_.dropped_circulating.fetch_add(1);
            return ForwardOutcome::DroppedCirculating;
        }
        if (!send(leaving_by, bytes)) return ForwardOutcome::SendFailed;
    }

    if (leaving_by == arrived_on) {
        counters_.bounced.fetch_add(1);
    } else if (arrived_on == LinkRole::Main) {
        counters_.forwarded_main_to_red.fetch_add(1);
    } else {
        counters_.forwarded_red_to_main.fetch_add(1);
    }
    if (stored_) stored_(arrived_on, bytes, first_pass);
    return leaving_by == arrived_on ? ForwardOutcome::Bounced : ForwardOutcome::Forwarded;
}

}  // namespace ecpair::redundancy
