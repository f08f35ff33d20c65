#include "ecpair/master/link_drain.hpp"

#include <algorithm>

#include "ecpair/common/log.hpp"

namespace ecpair::master {

std::size_t drain_link(link::Link& link, Bytes buffer, std::size_t limit, const FrameHandler& handler) {
    // One reading of both clocks maps every capture time of this call onto the steady clock.
    const auto steady_now = link::Clock::now();
    const auto system_now = std::chrono::system_clock::now();
    std::size_t taken = 0;
    while (taken < limit) {
        auto received = link.try_receive(buffer);
        if (!received) {
            logger("master")->debug("{}: {}", link.name(), received.error().message);
            break;
        }
        if (!*received) break;
        const auto& frame = **received;
        // A frame that came while this call ran is "now".
        const auto age = std::max<std::chrono::system_clock::duration>(system_now - frame.capture_time, {});
        handler(ConstBytes(buffer.data(), frame.size),
                steady_now - std::chrono::duration_cast<link::Clock::duration>(age));
        ++taken;
    }
    return taken;
}

}  // namespace ecpair::master
