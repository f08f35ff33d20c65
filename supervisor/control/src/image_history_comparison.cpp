// compare_image_histories: each member's SAFEOP/OP records indexed by cycle,
// then the cycles both hold walked in order; a pair is compared only when
// exactly one side is the mirror.

#include "ecpair/control/image_history_comparison.hpp"

#include <map>

#include <fmt/format.h>

namespace ecpair::control {
namespace {

std::map<std::uint64_t, const ImageHistoryEntry*> by_cycle(const ImageHistoryReply& history) {
    std::map<std::uint64_t, const ImageHistoryEntry*> cycles;
    for (const auto& e : history.entries()) {
        if (e.master_state() == "SAFEOP" || e.master_state() == "OP") cycles[e.cycle()] = &e;
    }
    return cycles;
}

}  // namespace

ImageHistoryComparison compare_image_histories(const ImageHistoryReply& a, const ImageHistoryReply& b,
                                               std::size_t newest) {
    const auto first = by_cycle(a);
    const auto second = by_cycle(b);
    std::vector<std::pair<const ImageHistoryEntry*, const ImageHistoryEntry*>> common;
    for (const auto& [cycle, entry] : first) {
        if (const auto it = second.find(cycle); it != second.end()) common.emplace_back(entry, it->second);
    }
    const std::size_t from = newest > 0 && common.size() > newest ? common.size() - newest : 0;

    ImageHistoryComparison result;
    for (std::size_t i = from; i < common.size(); ++i) {
        const auto& [x, y] = common[i];
        if (!x->mirrored() && !y->mirrored()) {
            result.both_active.push_back(x->cycle());
            continue;
        }
        if (x->mirrored() == y->mirrored()) continue;  // two mirrors: neither is the reference
        ++result.common_cycles;
        const CycleDifference d{x->cycle(), x->inputs_crc() != y->inputs_crc(), x->outputs_crc() != y->outputs_crc(),
                                x->master_state() != y->master_state()};
        if (d.inputs_differ || d.outputs_differ || d.state_differs) result.differ.push_back(d);
    }
    return result;
}

std::string ImageHistoryComparison::describe(std::size_t at_most) const {
    std::string text = fmt::format("{} cycles compared (ACTIVE's image against the mirror), {} differ", common_cycles,
                                   differ.size());
    for (std::size_t i = 0; i < differ.size() && i < at_most; ++i) {
        const auto& d = differ[i];
        text += fmt::format("; cycle {}:{}{}{}", d.cycle, d.inputs_differ ? " inputs" : "",
                            d.outputs_differ ? " outputs" : "", d.state_differs ? " master state" : "");
    }
    if (!both_active.empty()) {
        text += fmt::format("; {} cycle(s) recorded as the ACTIVE by both members (both sent), the first {}",
                            both_active.size(), both_active.front());
    }
    return text;
}

}  // namespace ecpair::control
