// One request, one frame: build it with the wire codec, let the segment
// carry it from MAIN, read the datagram back (see the header).

#include "ecpair/sim/segment_bus_access.hpp"

#include <array>

#include "ecpair/wire/frame.hpp"

namespace ecpair::sim {

Expected<bus::DatagramReply, bus::BusError> SegmentBusAccess::exchange(const bus::DatagramRequest& request) {
    std::lock_guard lock(mutex_);
    if (refusal_) return unexpected(bus::BusError{*refusal_, std::string(bus::to_string(*refusal_))});
    if (request.data.size() > wire::kMaxDatagramData) {
        return unexpected(bus::BusError{bus::BusErrc::InvalidRequest, "datagram too long"});
    }
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    ethernet.source = wire::MacAddress{{0x02, 0x00, 0x00, 0x00, 0x00, 0x01}};
    wire::FrameBuilder builder(buffer, ethernet);
    wire::DatagramHeader header;
    header.command = request.command;
    header.index = next_index_++;
    header.address = request.address;
    if (!builder.append(header, request.data)) {
        return unexpected(bus::BusError{bus::BusErrc::InvalidRequest, "datagram does not fit a frame"});
    }
    std::size_t size = builder.finish().size();
    now_ns_ += kTimePerFrameNs;
    ++frames_;
    const auto exit = segment_.carry(Side::Main, buffer, size, now_ns_);
    if (!exit) return unexpected(bus::BusError{bus::BusErrc::Timeout, "the frame died in the segment"});
    auto view = wire::ConstFrameView::parse(std::span<const std::uint8_t>(buffer.data(), size));
    if (!view || view->datagram_count() == 0) {
        return unexpected(bus::BusError{bus::BusErrc::Timeout, "the frame came back unreadable"});
    }
    const auto datagram = *view->begin();
    return bus::DatagramReply{{datagram.data().begin(), datagram.data().end()}, datagram.wkc(), datagram.irq()};
}

void SegmentBusAccess::refuse(std::optional<bus::BusErrc> reason) {
    std::lock_guard lock(mutex_);
    refusal_ = reason;
}

std::optional<bus::BusErrc> SegmentBusAccess::refusal() const {
    std::lock_guard lock(mutex_);
    return refusal_;
}

std::uint64_t SegmentBusAccess::frames() const {
    std::lock_guard lock(mutex_);
    return frames_;
}

void SegmentBusAccess::with_segment(const std::function<void(Segment&)>& f) {
    std::lock_guard lock(mutex_);
    f(segment_);
}

}  // namespace ecpair::sim
