// process_as_inactive: one pass over the frame's datagrams, touching only
// those that are CMF datagrams with a segment header this build understands.
// A datagram we cannot read is forwarded unchanged and without WKC credit, so
// the ACTIVE sees that its partner did not take it.

#include "ecpair/redundancy/cmf_inactive.hpp"

#include <algorithm>

#include "ecpair/redundancy/cmf_format.hpp"

namespace ecpair::redundancy {

bool process_as_inactive(wire::FrameView& frame, ConstBytes master_pd_in, ConstBytes standby_status) {
    bool carried_cmf = false;
    for (auto datagram : frame) {
        if (!is_cmf_datagram(datagram)) continue;
        const Bytes data = datagram.data();
        const auto segment = CmfSegmentHeader::decode(data, 0);
        if (!segment) continue;
        carried_cmf = true;
        if (segment->kind == CmfKind::MasterPdIn || segment->kind == CmfKind::StandbyStatus) {
            const ConstBytes section = segment->kind == CmfKind::MasterPdIn ? master_pd_in : standby_status;
            const Bytes payload = data.subspan(CmfSegmentHeader::kSize);
            if (segment->offset < section.size()) {
                const auto source = section.subspan(segment->offset);
                std::copy_n(source.begin(), std::min(source.size(), payload.size()), payload.begin());
            }
            datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + kCmfWriteWkcIncrement));
        } else {
            datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + kCmfReadWkcIncrement));
        }
    }
    return carried_cmf;
}

}  // namespace ecpair::redundancy
