// Fuzz target: frames of arbitrary bytes (format in cmf_corpus.hpp) fed to a
// CmfAssembler and processed by process_as_inactive. Whatever the bytes, the
// assembler must answer with an outcome or a typed error, and a cycle it
// reports complete must have exactly the sections of its layout.

#include <array>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "cmf_corpus.hpp"
#include "ecpair/redundancy/cmf_assembler.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"
#include "ecpair/wire/frame.hpp"

namespace {

using ecpair::redundancy::CmfAssembler;
using ecpair::redundancy::CmfKind;

void check_complete(const CmfAssembler& assembler) {
    const auto& layout = assembler.plan().layout();
    const auto& content = assembler.content();
    const bool sound = assembler.header().layout() == layout && content.slaves.size() == layout.slave_count &&
                       content.shadow_inputs.size() == layout.shadow_inputs_size &&
                       content.master_pd_out.size() == layout.section_size(CmfKind::MasterPdOut) &&
                       content.master_pd_in.size() == layout.section_size(CmfKind::MasterPdIn) &&
                       content.standby_status.size() == layout.section_size(CmfKind::StandbyStatus) &&
                       static_cast<std::uint32_t>(content.cycle) == static_cast<std::uint32_t>(assembler.header().cycle);
    if (!sound) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    CmfAssembler assembler(ecpair::redundancy::CmfPlan::make(ecpair::test::fuzz_layout(data[0])).value());
    const std::vector<std::uint8_t> pd_in(assembler.plan().layout().section_size(CmfKind::MasterPdIn), 0xC3);
    const std::vector<std::uint8_t> standby_status(ecpair::redundancy::CmfStandbyStatus::kSize, 0x3C);
    std::array<std::uint8_t, ecpair::wire::kMaxFrameSizeVlan> frame{};

    std::size_t at = 1;
    while (at + 2 <= size) {
        std::size_t length = static_cast<std::size_t>(data[at] | (data[at + 1] << 8));
        at += 2;
        length = std::min({length, size - at, frame.size()});
        std::copy_n(data + at, length, frame.begin());
        at += length;

        auto view = ecpair::wire::FrameView::parse(std::span(frame.data(), length));
        if (!view) continue;
        for (auto datagram : *view) {
            const auto outcome = assembler.feed(datagram);
            if (!outcome) {
                (void)outcome.error().describe();
            } else if (*outcome == CmfAssembler::Outcome::Completed) {
                check_complete(assembler);
            }
        }
        ecpair::redundancy::process_as_inactive(*view, pd_in, standby_status);
    }
    return 0;
}
