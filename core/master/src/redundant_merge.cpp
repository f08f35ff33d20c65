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

// The data of `merged` (a processed half, with its WKC) and `other` (the
// other processed half) become one pass's answer, by `rule`.
void merge_data(MergeRule rule, std::span<std::uint8_t> merged, std::uint16_t merged_wkc,
                std::span<const std::uint8_t> other, std::uint16_t other_wkc, std::span<const std::uint8_t> sent) {
    switch (rule) {
        case MergeRule::AsSent: return;
        case MergeRule::CountedCopy:
            if (merged_wkc == 0 && other_wkc != 0) std::copy(other.begin(), other.end(), merged.begin());
            return;
        case MergeRule::ChangedCopy:
            if (std::equal(merged.begin(), merged.end(), sent.begin()) &&
                !std::equal(other.begin(), other.end(), sent.begin())) {
                std::copy(other.begin(), other.end(), merged.begin());
            }
            return;
        case MergeRule::Or:
            for (std::size_t i = 0; i < merged.size(); ++i) merged[i] |= other[i];
            return;
        case MergeRule::ChangedBits:
            for (std::size_t i = 0; i < merged.size(); ++i) {
                merged[i] = static_cast<std::uint8_t>(sent[i] ^ ((merged[i] ^ sent[i]) | (other[i] ^ sent[i])));
            }
            return;
    }
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

// Each slave processed one half of a broken ring's datagram; what the other
// half carries in that slave's bytes is what the master sent.
MergeRule merge_rule_of(wire::Command command) {
    using wire::Command;
    switch (command) {
        // No slave writes into a NOP.
        case Command::Nop: return MergeRule::AsSent;
        // Slaves take the data and leave it as it is: both halves carry what was sent.
        case Command::Apwr:
        case Command::Fpwr:
        case Command::Bwr:
        case Command::Lwr: return MergeRule::AsSent;
        // One addressed slave counts what it did; the other half carries what was sent (APRW/FPRW: the written bytes).
        case Command::Aprd:
        case Command::Fprd:
        case Command::Aprw:
        case Command::Fprw: return MergeRule::CountedCopy;
        // One slave reads, every other slave writes the data and counts as well: the WKC cannot tell the reader's half.
        case Command::Armw:
        case Command::Frmw: return MergeRule::ChangedCopy;
        // Every slave ORs its register into the data (BRW writes what arrived, too).
        case Command::Brd:
        case Command::Brw: return MergeRule::Or;
        // Each slave's FMMUs replace only its own bits (LRW: its inputs, beside the outputs the others take).
        case Command::Lrd:
        case Command::Lrw: return MergeRule::ChangedBits;
    }
    // A reserved command code: no ESC processes it.
    return MergeRule::AsSent;
}

std::string_view to_string(MergeRule rule) {
    switch (rule) {
        case MergeRule::AsSent: return "as sent";
        case MergeRule::CountedCopy: return "the copy that counted";
        case MergeRule::ChangedCopy: return "the copy that changed";
        case MergeRule::Or: return "OR";
        case MergeRule::ChangedBits: return "the bits each copy changed";
    }
    return "?";
}

Expected<MergeResult, MergeError> merge_copies(ConstBytes sent, const ReturnedCopy& main_copy,
                                               const ReturnedCopy& red_copy, Bytes out) {
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
    auto as_sent = wire::ConstFrameView::parse(sent);
    if (!as_sent) return unexpected(MergeError{"sent frame: " + as_sent.error().describe()});
    if (merged->datagram_count() != other->datagram_count() || merged->datagram_count() != as_sent->datagram_count()) {
        return unexpected(
            MergeError{fmt::format("copies differ: {} vs {} datagrams ({} sent)", merged->datagram_count(),
                                   other->datagram_count(), as_sent->datagram_count())});
    }
    // Only a broken ring gives two processed halves; an unprocessed copy adds nothing but its (zero) WKC.
    const bool both_processed = processed(base) && processed(other_copy);
    auto o = other->begin();
    auto s = as_sent->begin();
    for (auto d : *merged) {
        const auto od = *o;
        const auto sd = *s;
        ++o;
        ++s;
        if (od.command() != d.command() || od.index() != d.index() || od.length() != d.length() ||
            sd.command() != d.command() || sd.length() != d.length()) {
            return unexpected(MergeError{fmt::format("copies differ at datagram offset {}", d.frame_offset())});
        }
        if (both_processed) merge_data(merge_rule_of(d.command()), d.data(), d.wkc(), od.data(), od.wkc(), sd.data());
        d.set_wkc(static_cast<std::uint16_t>(d.wkc() + od.wkc()));
        d.set_irq(static_cast<std::uint16_t>(d.irq() | od.irq()));
    }
    return result;
}

}  // namespace ecpair::master
