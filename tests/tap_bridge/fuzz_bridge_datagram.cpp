// Fuzz target: bytes from the bus, read by the bridge as every role reads
// them. The input is taken both as one datagram's data
// (decode_bridge_datagram) and as a whole EtherCAT frame passing an INACTIVE
// end (process, forwarded) and returning to an ACTIVE end (returned, complete).
// Whatever the bytes: no crash, and what reaches a TAP queue is a whole
// Ethernet frame that some valid datagram carried.

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "ecpair/tap_bridge/bridge_channel.hpp"
#include "ecpair/wire/frame.hpp"

namespace {

using namespace ecpair::tap_bridge;

void check_inbound(FrameQueue& queue) {
    queue.pop_while([](ecpair::ConstBytes frame) {
        if (frame.size() < kMinBridgedFrame || frame.size() > largest_frame(kMaxBridgeDatagramData)) std::abort();
        return true;
    });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const ecpair::ConstBytes input(data, size);
    if (const auto d = decode_bridge_datagram(input)) {
        std::size_t total = 0;
        std::size_t frames = 0;
        d->for_each_frame([&](ecpair::ConstBytes frame) {
            if (frame.size() < kMinBridgedFrame || frame.data() < data || frame.data() + frame.size() > data + size) {
                std::abort();
            }
            total += kFrameLengthPrefix + frame.size();
            ++frames;
        });
        if (total != d->header.length || frames != d->header.frame_count) std::abort();
    }

    static BridgeChannel inactive(BridgeChannelOptions{0x1111, kMaxBridgeDatagramData, 8});
    static BridgeChannel active(BridgeChannelOptions{0x2222, kMaxBridgeDatagramData, 8});
    static const bool roles = [] {
        inactive.role_changed(false);
        active.role_changed(true);
        inactive.offer(std::vector<std::uint8_t>(64, 0x42));  // something to answer polls with
        return true;
    }();
    (void)roles;

    std::vector<std::uint8_t> frame(data, data + size);
    if (auto view = ecpair::wire::FrameView::parse(frame)) {
        inactive.process(ecpair::master::LinkRole::Main, *view, true);
        inactive.forwarded(ecpair::master::LinkRole::Main, frame, true);
        active.returned(ecpair::master::LinkRole::Red, frame);
        active.complete(0, ecpair::master::ReturnedCopy{frame, ecpair::master::CopyPath::ThroughRing},
                        ecpair::master::ReturnedCopy{});
    }
    if (inactive.outbound_depth() == 0) inactive.offer(std::vector<std::uint8_t>(64, 0x42));
    check_inbound(inactive.inbound());
    check_inbound(active.inbound());
    return 0;
}
