// One request = one frame with one datagram. The reply is the same frame
// coming back: an EtherCAT frame whose source MAC still carries our NIC
// bytes and whose datagram has our index and command. Anything else on the
// link (foreign frames, stale replies of an earlier attempt) is skipped.

#include "ecpair/bus/link_bus_access.hpp"

#include <poll.h>

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace ecpair::bus {

LinkBusAccess::LinkBusAccess(link::Link& link, link::Link* also_receive_on) : link_(link), other_(also_receive_on) {}

Expected<std::optional<std::size_t>, BusError> LinkBusAccess::receive_any(Bytes buffer,
                                                                          std::chrono::nanoseconds timeout) {
    if (other_ == nullptr) {
        auto received = link_.receive(buffer, timeout);
        if (!received) return unexpected(BusError{BusErrc::LinkFailure, received.error().message});
        if (!received->has_value()) return std::optional<std::size_t>();
        return std::optional<std::size_t>((*received)->size);
    }
    std::array<pollfd, 2> fds{pollfd{link_.selectable_fd(), POLLIN, 0}, pollfd{other_->selectable_fd(), POLLIN, 0}};
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count();
    if (::poll(fds.data(), fds.size(), static_cast<int>(std::clamp<std::int64_t>(ms, 1, 1000))) <= 0) {
        return std::optional<std::size_t>();
    }
    for (link::Link* link : {&link_, other_}) {
        auto received = link->try_receive(buffer);
        if (!received) return unexpected(BusError{BusErrc::LinkFailure, received.error().message});
        if (received->has_value()) return std::optional<std::size_t>((*received)->size);
    }
    return std::optional<std::size_t>();
}

Expected<DatagramReply, BusError> LinkBusAccess::exchange(const DatagramRequest& request) {
    if (request.data.size() > wire::kMaxDatagramData) {
        return unexpected(BusError{BusErrc::InvalidRequest,
                                   fmt::format("{} bytes do not fit in one datagram", request.data.size())});
    }
    const auto nic = wire::NicBytes::of(link_.mac());
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> tx{};
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> rx{};

    for (std::uint32_t attempt = 0; attempt <= request.retries; ++attempt) {
        const std::uint8_t index = next_index_++;
        wire::SourceMac source;
        source.retry_index = static_cast<std::uint8_t>(attempt & 0x07);
        source.frame_id = next_frame_id_++;
        source.nic = nic;
        wire::EthernetHeader ethernet;
        ethernet.destination = wire::MacAddress::broadcast();
        ethernet.source = source.encode();
        wire::FrameBuilder builder(tx, ethernet);
        wire::DatagramHeader header;
        header.command = request.command;
        header.index = index;
        header.address = request.address;
        if (!builder.append(header, request.data)) {
            return unexpected(BusError{BusErrc::InvalidRequest, "datagram does not fit in a frame"});
        }
        const auto frame = builder.finish();
        if (auto sent = link_.send(frame); !sent) {
            return unexpected(BusError{BusErrc::LinkFailure, sent.error().message});
        }
        ++frames_sent_;

        const auto deadline = link::Clock::now() + request.timeout;
        for (auto now = link::Clock::now(); now < deadline; now = link::Clock::now()) {
            auto received = receive_any(rx, deadline - now);
            if (!received) return unexpected(received.error());
            if (!received->has_value()) continue;
            auto view = wire::ConstFrameView::parse(std::span<const std::uint8_t>(rx.data(), **received));
            if (!view || view->datagram_count() == 0) continue;
            if (wire::SourceMac::decode(view->ethernet().source).nic != nic) continue;
            const auto datagram = *view->begin();
            if (datagram.index() != index || datagram.command() != request.command ||
                datagram.length() != request.data.size()) {
                continue;
            }
            return DatagramReply{{datagram.data().begin(), datagram.data().end()}, datagram.wkc(), datagram.irq()};
        }
        ++timeouts_;
        logger("bus")->debug("{} 0x{:08x}: no reply within {} ms (attempt {})", wire::to_string(request.command),
                             request.address, request.timeout.count(), attempt + 1);
    }
    return unexpected(BusError{BusErrc::Timeout,
                               fmt::format("{} at 0x{:08x}: no reply after {} attempts on {}",
                                           wire::to_string(request.command), request.address,
                                           request.retries + 1, link_.name())});
}

}  // namespace ecpair::bus
