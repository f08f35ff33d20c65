// Fuzzes the decoder of link guard messages: any bytes give a message that
// encodes back to the same bytes, or an error naming an offset inside them.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "ecpair/linkguard/guard_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto decoded = ecpair::linkguard::decode(ecpair::ConstBytes(data, size));
    if (decoded) {
        const auto again = ecpair::linkguard::encode(*decoded);
        if (size != again.size() || std::memcmp(again.data(), data, size) != 0) std::abort();
    } else if (size > 0 && decoded.error().offset >= size) {
        std::abort();
    }
    return 0;
}
