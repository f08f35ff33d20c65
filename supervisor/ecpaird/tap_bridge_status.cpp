#include "tap_bridge_status.hpp"

namespace ecpair::daemon {

void fill_tap_bridge_status(const tap_bridge::TapBridge& bridge, control::TapBridgeStatus& out) {
    const auto s = bridge.status();
    out.set_name(s.name);
    for (const auto& a : s.addresses) out.add_addresses(a);
    out.set_mac(s.mac);
    out.set_mtu(static_cast<std::uint32_t>(s.mtu));
    out.set_role(s.flow.active ? "ACTIVE" : "INACTIVE");
    out.set_flowing(s.flow.flowing);
    out.set_why_not(s.flow.why_not);
    const auto& c = s.counters;
    out.set_tx_frames(c.tx_frames);
    out.set_tx_bytes(c.tx_bytes);
    out.set_rx_frames(c.rx_frames);
    out.set_rx_bytes(c.rx_bytes);
    out.set_polls_sent(c.polls_sent);
    out.set_polls_answered(c.polls_answered);
    out.set_polls_unanswered(c.polls_unanswered);
    out.set_answers_given(c.answers_given);
    out.set_duplicates(c.duplicates);
    out.set_dropped_oversized(c.dropped_oversized);
    out.set_dropped_tx_queue_full(c.dropped_tx_queue_full);
    out.set_dropped_rx_queue_full(c.dropped_rx_queue_full);
    out.set_dropped_garbled(c.dropped_garbled);
    out.set_dropped_lost(c.dropped_lost);
    out.set_dropped_tap_write(c.dropped_tap_write);
    out.set_outbound_depth(static_cast<std::uint32_t>(s.outbound_depth));
    out.set_inbound_depth(static_cast<std::uint32_t>(s.inbound_depth));
    out.set_queue_capacity(static_cast<std::uint32_t>(s.queue_capacity));
}

}  // namespace ecpair::daemon
