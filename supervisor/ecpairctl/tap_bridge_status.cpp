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

void write_tap_bridge_json(JsonWriter& json, const control::StatusReply& status) {
    json.key("tap_bridge");
    if (!status.has_tap_bridge()) {
        json.null();
        return;
    }
    const auto& t = status.tap_bridge();
    json.begin_object().key("name").value(t.name()).key("addresses").begin_array();
    for (const auto& a : t.addresses()) json.value(a);
    json.end_array().key("mac").value(t.mac()).key("mtu").value(t.mtu()).key("role").value(t.role());
    json.key("flowing").value(t.flowing()).key("why_not").value(t.why_not());
    json.key("tx_frames").value(t.tx_frames()).key("tx_bytes").value(t.tx_bytes());
    json.key("rx_frames").value(t.rx_frames()).key("rx_bytes").value(t.rx_bytes());
    json.key("polls_sent").value(t.polls_sent()).key("polls_answered").value(t.polls_answered());
    json.key("polls_unanswered").value(t.polls_unanswered()).key("answers_given").value(t.answers_given());
    json.key("duplicates").value(t.duplicates()).key("dropped_oversized").value(t.dropped_oversized());
    json.key("dropped_tx_queue_full").value(t.dropped_tx_queue_full());
    json.key("dropped_rx_queue_full").value(t.dropped_rx_queue_full());
    json.key("dropped_garbled").value(t.dropped_garbled()).key("dropped_lost").value(t.dropped_lost());
    json.key("dropped_tap_write").value(t.dropped_tap_write()).key("outbound_depth").value(t.outbound_depth());
    json.key("inbound_depth").value(t.inbound_depth()).key("queue_capacity").value(t.queue_capacity());
    json.end_object();
}

}  // namespace ecpair::ctl
