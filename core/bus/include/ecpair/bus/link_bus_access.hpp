#pragma once
// BusAccess over one link with nobody else sending: one frame per request,
// wait for it to come back (matched by datagram index and our NIC bytes in
// the source MAC), retry with the retry index in the source MAC. Used by
// offline tools (ecpairctl scan) and tests, not by the cyclic master.
//
// In a redundant ring a frame sent on MAIN passes every slave and comes back
// on the RED adapter: give that adapter as `also_receive_on` and replies are
// taken from either link (nothing is sent on it).

#include <cstdint>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/link/link.hpp"

namespace ecpair::bus {

class LinkBusAccess final : public BusAccess {
public:
    explicit LinkBusAccess(link::Link& link, link::Link* also_receive_on = nullptr);

    Expected<DatagramReply, BusError> exchange(const DatagramRequest& request) override;

    std::uint64_t frames_sent() const { return frames_sent_; }
    std::uint64_t timeouts() const { return timeouts_; }

private:
    // Waits up to `timeout` for a frame on either link.
    Expected<std::optional<std::size_t>, BusError> receive_any(Bytes buffer, std::chrono::nanoseconds timeout);

    link::Link& link_;
    link::Link* other_;
    std::uint8_t next_index_ = 0;
    std::uint8_t next_frame_id_ = 0;
    std::uint64_t frames_sent_ = 0;
    std::uint64_t timeouts_ = 0;
};

}  // namespace ecpair::bus
