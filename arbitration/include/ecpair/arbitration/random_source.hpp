#pragma once
// Where backoff times come from. Injected, so that every arbitration path
// can be replayed in a test with the draws it needs.

#include <chrono>
#include <cstdint>
#include <random>

namespace ecpair::arbitration {

class RandomSource {
public:
    virtual ~RandomSource() = default;
    // A duration drawn uniformly from [low, high] (low when high <= low).
    virtual std::chrono::nanoseconds between(std::chrono::nanoseconds low, std::chrono::nanoseconds high) = 0;
};

// The production source: a Mersenne twister seeded from std::random_device
// (and so different on the two controllers of a pair).
class SystemRandom final : public RandomSource {
public:
    SystemRandom();
    explicit SystemRandom(std::uint64_t seed) : engine_(seed) {}
    std::chrono::nanoseconds between(std::chrono::nanoseconds low, std::chrono::nanoseconds high) override;

private:
    std::mt19937_64 engine_;
};

}  // namespace ecpair::arbitration
