#pragma once
// min / p50 / p99 / max of a set of measurements, for the benchmarks'
// printed figures.

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace ecpair::bench {

inline std::string spread(std::vector<double> values, const char* unit) {
    if (values.empty()) return "no runs";
    std::sort(values.begin(), values.end());
    auto at = [&values](double p) {
        const auto index = static_cast<std::size_t>(p / 100.0 * static_cast<double>(values.size() - 1) + 0.5);
        return values[std::min(index, values.size() - 1)];
    };
    return fmt::format("min {:.1f} / p50 {:.1f} / p99 {:.1f} / max {:.1f} {} ({} runs)", values.front(), at(50), at(99),
                       values.back(), unit, values.size());
}

}  // namespace ecpair::bench
