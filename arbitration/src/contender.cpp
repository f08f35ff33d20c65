#include "ecpair/arbitration/contender.hpp"

#include <fmt/format.h>

namespace ecpair::arbitration {

Comparison compare_reach(const Contender& ours, const Contender& theirs) {
    if (ours.slaves_reached == theirs.slaves_reached) return {};
    return {ours.slaves_reached > theirs.slaves_reached ? Preference::Ours : Preference::Theirs,
            DecidedBy::SlavesReached};
}

Comparison compare(const Contender& ours, const Contender& theirs) {
    if (const auto by_reach = compare_reach(ours, theirs); by_reach.preference != Preference::Undecided) {
        return by_reach;
    }
    if (ours.epoch != theirs.epoch) {
        return {ours.epoch < theirs.epoch ? Preference::Ours : Preference::Theirs, DecidedBy::Epoch};
    }
    if (ours.member != theirs.member) {
        return {ours.member < theirs.member ? Preference::Ours : Preference::Theirs, DecidedBy::Mac};
    }
    return {};
}

std::string_view to_string(DecidedBy criterion) {
    switch (criterion) {
        case DecidedBy::SlavesReached: return "it reaches more slaves";
        case DecidedBy::Epoch: return "it has owned the bus longer (older epoch)";
        case DecidedBy::Mac: return "same reach and epoch: lower MAIN MAC";
        case DecidedBy::Nothing: return "undecided";
    }
    return "undecided";
}

std::string member_name(std::uint64_t member) {
    return fmt::format("{:02x}:{:02x}:{:02x}:{:02x}:{:02x}:{:02x}", (member >> 40) & 0xFF, (member >> 32) & 0xFF,
                       (member >> 24) & 0xFF, (member >> 16) & 0xFF, (member >> 8) & 0xFF, member & 0xFF);
}

}  // namespace ecpair::arbitration
