#include "ecpair/arbitration/random_source.hpp"

namespace ecpair::arbitration {

SystemRandom::SystemRandom() : engine_(std::random_device{}()) {}

std::chrono::nanoseconds SystemRandom::between(std::chrono::nanoseconds low, std::chrono::nanoseconds high) {
    if (high <= low) return low;
    std::uniform_int_distribution<std::int64_t> draw(low.count(), high.count());
    return std::chrono::nanoseconds(draw(engine_));
}

}  // namespace ecpair::arbitration
