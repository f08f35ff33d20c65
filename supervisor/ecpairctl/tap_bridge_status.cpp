#include "tap_bridge_status.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

namespace ecpair::ctl {

void print_tap_bridge_status(std::ostream& out, const control::StatusReply& status) {
    if (!status.has_tap_bridge()) return;
    const auto& t = status.tap_bridge();
    std::string addresses;
    for (const auto& a : t.addresses()) addresses += (addresses.empty() ? "" : " ") + a;
    fmt::print(out, "  tap bridge {} ({}, MAC {}, MTU {}): {}, {}\n", t.name(), addresses.empty() ? "no address" : addresses,
               t.mac(), t.mtu(), t.role(), t.flowing() ? "flowing" : "NOT flowing: " + t.why_not());
    fmt::print(out, "    sent {} frames ({} bytes), received {} frames ({} bytes), queued {} out / {} in of {}\n",
               t.tx_frames(), t.tx_bytes(), t.rx_frames(), t.rx_bytes(), t.outbound_depth(), t.inbound_depth(),
               t.queue_capacity());
    if (t.role() == "ACTIVE") {
        fmt::print(out, "    polls {} sent, {} answered, {} unanswered\n", t.polls_sent(), t.polls_answered(),
                   t.polls_unanswered());
    } else {
        fmt::print(out, "    polls answered {}\n", t.answers_given());
    }
    fmt::print(out, "    dropped: {} oversized, {} queue full out, {} queue full in, {} garbled, {} lost, {} TAP write; "
               "{} duplicate copies\n",
               t.dropped_oversized(), t.dropped_tx_queue_full(), t.dropped_rx_queue_full(), t.dropped_garbled(),
               t.dropped_lost(), t.dropped_tap_write(), t.duplicates());
}

}  // namespace ecpair::ctl
