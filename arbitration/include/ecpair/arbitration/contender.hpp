#pragma once
// What a master that owns (or owned) the bus claims in its Cyclic Master Red
// Frame, and the rule that picks one of two such masters.
//
// The rule (documented in docs/ARBITRATION.md), chosen to disturb the
// machine least:
//   1. the master that reaches more slaves keeps the bus (after a double line
//      break each half had its own ACTIVE; the bigger half's slaves need not
//      change master at all, the smaller half's slaves keep their state and
//      process data under the winner);
//   2. then the older term: the lower epoch, i.e. the master that has owned
//      the bus for longer (its application state is the one the machine
//      followed);
//   3. then the lower MAIN adapter MAC, which two masters never share.

#include <cstdint>
#include <string>

namespace ecpair::arbitration {

struct Contender {
    std::uint32_t epoch = 0;           // its ACTIVE term; a master that takes the bus counts one past all it heard
    std::uint16_t slaves_reached = 0;  // slaves that answered its last complete cycle (0: unknown)
    std::uint64_t member = 0;          // its MAIN adapter's MAC as a 48-bit number
    friend bool operator==(const Contender&, const Contender&) = default;
};

enum class Preference : std::uint8_t { Ours, Theirs, Undecided };

// Which criterion decided (for the event that says why).
enum class DecidedBy : std::uint8_t { SlavesReached, Epoch, Mac, Nothing };

struct Comparison {
    Preference preference = Preference::Undecided;
    DecidedBy decided_by = DecidedBy::Nothing;
};

// The full rule (1, 2, 3).
Comparison compare(const Contender& ours, const Contender& theirs);
// Rule 1 alone: decided only when the two reach different numbers of slaves.
Comparison compare_reach(const Contender& ours, const Contender& theirs);

std::string_view to_string(DecidedBy criterion);
// "02:00:00:00:00:11"
std::string member_name(std::uint64_t member);

}  // namespace ecpair::arbitration
