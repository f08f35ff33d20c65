// The default batch send of a Link: one send() per frame, stopping at the
// first the adapter refuses.

#include "ecpair/link/link.hpp"

namespace ecpair::link {

BatchSendResult Link::send_batch(std::span<const ConstBytes> frames) {
    BatchSendResult result;
    for (const ConstBytes frame : frames) {
        if (auto sent = send(frame); !sent) {
            result.error = std::move(sent).error();
            return result;
        }
        ++result.sent;
    }
    return result;
}

}  // namespace ecpair::link
