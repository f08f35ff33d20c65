// Builds the seed corpus: single cycles of both layouts, MAIN and RED copies
// after the INACTIVE processed them, cycles out of order, and a partner with
// other parameters, all as CmfWriter writes them.

#include "cmf_corpus.hpp"

#include <algorithm>

#include "cmf_test_support.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"

namespace ecpair::test {
namespace {

constexpr std::uint8_t kSmall = 0;
constexpr std::uint8_t kLarge = 1;

void append_frame(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& frame) {
    out.push_back(static_cast<std::uint8_t>(frame.size()));
    out.push_back(static_cast<std::uint8_t>(frame.size() >> 8));
    out.insert(out.end(), frame.begin(), frame.end());
}

std::vector<SentCmfFrame> cycle_frames(const redundancy::CmfLayout& layout, std::uint64_t cycle) {
    const TestContent content(layout, cycle);
    return write_cmf(layout, content.content);
}

CorpusEntry entry(std::string name, std::uint8_t selector, const std::vector<SentCmfFrame>& frames) {
    CorpusEntry e{std::move(name), {selector}};
    for (const auto& f : frames) append_frame(e.bytes, f.bytes);
    return e;
}

}  // namespace

redundancy::CmfLayout fuzz_layout(std::uint8_t selector) {
    return (selector & 1) == kSmall ? small_layout() : large_layout();
}

std::vector<CorpusEntry> make_cmf_corpus() {
    std::vector<CorpusEntry> corpus;
    corpus.push_back(entry("small_one_cycle", kSmall, cycle_frames(small_layout(), 1)));
    corpus.push_back(entry("large_one_cycle", kLarge, cycle_frames(large_layout(), 3)));

    // The MAIN and the RED copy, both processed by the INACTIVE on their way.
    auto processed = cycle_frames(large_layout(), 2);
    const std::vector<std::uint8_t> pd_in(large_layout().parameters.master_pd_in_size, 0x5A);
    const std::vector<std::uint8_t> standby_status(redundancy::CmfStandbyStatus::kSize, 0x21);
    for (auto& f : processed) {
        auto view = wire::FrameView::parse(f.bytes);
        redundancy::process_as_inactive(*view, pd_in, standby_status);
    }
    auto copies = processed;
    copies.insert(copies.end(), processed.begin(), processed.end());
    corpus.push_back(entry("large_processed_copies", kLarge, copies));

    // Cycle 5's frames backwards, then cycle 4 (stale), then cycle 6.
    auto mixed = cycle_frames(large_layout(), 5);
    std::reverse(mixed.begin(), mixed.end());
    for (auto& f : cycle_frames(large_layout(), 4)) mixed.push_back(std::move(f));
    for (auto& f : cycle_frames(large_layout(), 6)) mixed.push_back(std::move(f));
    corpus.push_back(entry("large_cycles_out_of_order", kLarge, mixed));

    redundancy::CmfLayout other = small_layout();
    other.parameters.cycle_time = std::chrono::microseconds(500);
    corpus.push_back(entry("small_partner_differs", kSmall, cycle_frames(other, 7)));
    return corpus;
}

}  // namespace ecpair::test
