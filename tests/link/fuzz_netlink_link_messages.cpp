// Fuzz target: the rtnetlink link-message decoder must turn any byte
// sequence into links or an error, never a crash or an out-of-bounds read.
// When it succeeds, what it reports must be self-consistent.

#include <cstdint>
#include <cstdlib>

#include <linux/if.h>

#include "netlink_link_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const ecpair::ConstBytes input(data, size);
    auto batch = ecpair::link::detail::decode_netlink_link_messages(input);
    if (!batch) {
        if (batch.error().offset > size || batch.error().problem.empty()) std::abort();
        return 0;
    }
    for (const auto& link : batch->links) {
        if (link.name.size() >= IFNAMSIZ) std::abort();
        (void)link.is_up();
    }
    return 0;
}
