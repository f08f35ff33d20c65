#pragma once
// What the consumer of the EventQueue gets: an event as it was raised, or,
// for a kind that repeats every cycle or frame while a fault lasts
// (RepeatPolicy), a summary of the events since the last report or the end
// of the fault, with counts per subject (which datagram, which link).

#include <chrono>
#include <cstdint>
#include <string_view>
#include <vector>

#include "ecpair/master/event.hpp"

namespace ecpair::master {

enum class Repetition : std::uint8_t {
    Single,   // the event itself; for a kind that repeats, the first of a fault
    Summary,  // the events of a fault since its previous report (at most one a second)
    End,      // the fault is over: none for the quiet time
};

// "" (Single), "summary", "end": the operator API's EventMessage.repeat.
std::string_view to_string(Repetition repetition);

struct SubjectCount {
    Event last;                // the subject's latest event: what a summary describes
    std::uint64_t count = 0;   // Summary: since the previous report; End: since the fault started
};

struct EventReport {
    // Single: the event. Summary, End: its kind, and the cycle and time the
    // report was made at (a..d are those of the first subject's latest event).
    Event event;
    Repetition repetition = Repetition::Single;
    std::uint64_t count = 1;          // events this report stands for (End: since the previous report)
    std::uint64_t total = 1;          // events since the fault started (its first included)
    std::uint64_t start_cycle = 0;    // the cycle of the fault's first event
    std::uint64_t first_cycle = 0;    // Summary: the cycles `count` covers; End: start_cycle
    std::uint64_t last_cycle = 0;     // the cycle of the latest event counted
    std::chrono::nanoseconds span{};  // Summary: the time since the previous report; End: first to last event
    std::vector<SubjectCount> subjects;  // Summary: those with events in `count`; End: all, with their totals
    std::uint64_t other = 0;             // events of subjects beyond those counted apart (as `subjects`)
};

}  // namespace ecpair::master
