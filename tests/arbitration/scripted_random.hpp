#pragma once
// A RandomSource for tests: hands out the fractions it was given, in turn
// (0.0 = low, 1.0 = high), and records what it was asked for.

#include <chrono>
#include <utility>
#include <vector>

#include "ecpair/arbitration/random_source.hpp"

namespace ecpair::test {

class ScriptedRandom final : public arbitration::RandomSource {
public:
    explicit ScriptedRandom(std::vector<double> fractions) : fractions_(std::move(fractions)) {}

    std::chrono::nanoseconds between(std::chrono::nanoseconds low, std::chrono::nanoseconds high) override {
        asked.emplace_back(low, high);
        const double f = fractions_.empty() ? 0.0 : fractions_[next_++ % fractions_.size()];
        return low + std::chrono::nanoseconds(static_cast<std::int64_t>(static_cast<double>((high - low).count()) * f));
    }

    std::vector<std::pair<std::chrono::nanoseconds, std::chrono::nanoseconds>> asked;

private:
    std::vector<double> fractions_;
    std::size_t next_ = 0;
};

}  // namespace ecpair::test
