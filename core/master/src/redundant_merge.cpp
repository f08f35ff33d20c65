#include "ecpair/master/redundant_merge.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/wire/frame.hpp"

namespace ecpair::master {
namespace {

bool processed(const ReturnedCopy& copy) {
    return copy.path == CopyPath::ThroughRing || copy.path == CopyPath::BouncedMain ||
           copy.path == CopyPath::BouncedRed;
}

}  // namespace

std::string_view to_string(CopyPath path) {
    switch (path) {
        case CopyPath::Missing: return "missing";
        case CopyPath::ThroughRing: return "through the ring";
        case CopyPath::Unprocessed: return "unprocessed";
        case CopyPath::BouncedMain: return "bounced on MAIN";
        case CopyPath::BouncedRed: return "bounced on RED";
    }
    return "?";
}

CopyPath classify(LinkRole sent_on, LinkRole arrived_on) {
    if (sent_on == LinkRole::Main) return arrived_on == LinkRole::Red ? CopyPath::ThroughRing : CopyPath::BouncedMain;
    return arrived_on == LinkRole::Main ? CopyPath::Unprocessed : CopyPath::BouncedRed;
}

Expected<MergeResult, MergeError> merge_copies(const ReturnedCopy& main_copy, const ReturnedCopy& red_copy, Bytes out) {
    const bool have_main = main_copy.path != CopyPath::Missing;
    const bool have_red = red_copy.path != CopyPath::Missing;
    if (!have_main && !have_red) return unexpected(MergeError{"neither copy came back"});

    MergeResult result;
    result.ring_closed = main_copy.path == CopyPath::ThroughRing;
    result.ring_broken = main_copy.path == CopyPath::BouncedMain || red_copy.path == CopyPath::BouncedRed;
    result.complete = main_copy.path == CopyPath::ThroughRing ||
                      (main_copy.path == CopyPath::BouncedMain && red_copy.path == CopyPath::BouncedRed);

    // Start from the copy that carries processed data (MAIN's when both do).
    const ReturnedCopy& base = (have_main && (processed(main_copy) || !processed(red_copy))) ? main_copy : red_copy;
    const ReturnedCopy& other_copy = (&base == &main_copy) ? red_copy : main_copy;
    if (out.size() < base.frame.size()) return unexpected(MergeError{"output buffer too small"});
    std::copy(base.frame.begin(), base.frame.end(), out.begin());
    result.size = base.frame.size();
    if (other_copy.path == CopyPath::Missing) return result;

    auto merged = wire::FrameView::parse(out.first(result.size));
    if (!merged) return unexpected(MergeError{"merged frame: " + merged.error().describe()});
    auto other = wire::ConstFrameView::parse(other_copy.frame);
    if (!other) return unexpected(MergeError{"other copy: " + other.error().describe()});
    if (merged->datagram_count() != other->datagram_count()) {
        return unexpected(MergeError{fmt::format("copies differ: {} vs {} datagrams", merged->datagram_count(),
                                                 other->datagram_count())});
    }
    const bool or_data = processed(base) && processed(other_copy);
    auto o = other->begin();
    for (auto d : *merged) {
        const auto od = *o;
        ++o;
        if (od.command() != d.command() || od.index() != d.index() || od.length() != d.length()) {
            return unexpected(MergeError{fmt::format("copies differ at datagram offset {}", d.frame_offset())});
        }
        if (or_data) {
            auto data = d.data();
            const auto other_data = od.data();
            for (std::size_t i = 0; i < data.size(); ++i) data[i] |= other_data[i];
        }
        d.set_wkc(static_cast<std::uint16_t>(d.wkc() + od.wkc()));
    }
    return result;
}

}  // namespace ecpair::master
