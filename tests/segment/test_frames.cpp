#include "test_frames.hpp"

#include <algorithm>
#include <stdexcept>

namespace ecpair::test {

namespace {

wire::ConstFrameView parsed(const TestFrame& frame) {
    auto view = wire::ConstFrameView::parse(frame.bytes());
    if (!view) throw std::runtime_error("test frame does not parse: " + view.error().describe());
    return *view;
}

wire::ConstDatagramView datagram(const TestFrame& frame, std::size_t n) {
    const auto view = parsed(frame);
    if (n >= view.datagram_count()) throw std::runtime_error("test frame has fewer datagrams");
    auto it = view.begin();
    for (std::size_t i = 0; i < n; ++i) ++it;
    return *it;
}

}  // namespace

wire::MacAddress master_mac() { return wire::MacAddress{{0x00, 0x00, 0x00, 0x1c, 0x2d, 0x3e}}; }

TestFrame ethercat_frame(const std::vector<DatagramSpec>& datagrams, bool unpadded) {
    TestFrame frame;
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    ethernet.source = master_mac();
    wire::FrameBuilder builder(frame.buffer, ethernet);
    for (const auto& spec : datagrams) {
        wire::DatagramHeader header;
        header.command = spec.command;
        header.address = spec.address;
        if (!builder.append(header, spec.data)) throw std::runtime_error("datagrams do not fit one frame");
    }
    const Bytes finished = builder.finish();
    frame.size = finished.size();
    if (unpadded) {
        const auto view = parsed(frame);
        frame.size = view.end_offset();
        std::fill(frame.buffer.begin() + static_cast<std::ptrdiff_t>(frame.size), frame.buffer.end(), 0xEE);
    }
    return frame;
}

TestFrame single(wire::Command command, std::uint32_t address, std::size_t length) {
    return ethercat_frame({DatagramSpec{command, address, std::vector<std::uint8_t>(length, 0)}});
}

TestFrame non_ethercat_frame() {
    TestFrame frame;
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    ethernet.source = master_mac();
    ethernet.ether_type = 0x0800;
    ethernet.encode(frame.buffer);
    for (std::size_t i = ethernet.size(); i < wire::kMinFrameSize; ++i) frame.buffer[i] = static_cast<std::uint8_t>(i);
    frame.size = wire::kMinFrameSize;
    return frame;
}

wire::DatagramHeader header_of(const TestFrame& frame, std::size_t n) { return datagram(frame, n).header(); }

std::uint16_t wkc_of(const TestFrame& frame, std::size_t n) { return datagram(frame, n).wkc(); }

std::vector<std::uint8_t> data_of(const TestFrame& frame, std::size_t n) {
    const auto data = datagram(frame, n).data();
    return {data.begin(), data.end()};
}

wire::MacAddress source_of(const TestFrame& frame) { return parsed(frame).ethernet().source; }

}  // namespace ecpair::test
