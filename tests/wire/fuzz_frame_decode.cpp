// Fuzz target: any byte string through FrameView::parse. A frame that
// parses must iterate exactly datagram_count() datagrams inside the buffer,
// and every header must survive a decode/encode round trip.

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ecpair/wire/frame.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::uint8_t> bytes(data, data + size);
    auto view = ecpair::wire::FrameView::parse(bytes);
    if (!view) {
        (void)view.error().describe();
        return 0;
    }
    std::size_t count = 0;
    for (auto d : *view) {
        if (d.frame_offset() + d.size() > bytes.size()) std::abort();
        const auto header = d.header();
        std::uint8_t encoded[ecpair::wire::kDatagramHeaderSize];
        header.encode(encoded);
        if (std::memcmp(encoded, d.bytes().data(), sizeof encoded) != 0) std::abort();
        (void)d.wkc();
        ++count;
    }
    if (count != view->datagram_count() || view->end_offset() > bytes.size()) std::abort();
    return 0;
}
