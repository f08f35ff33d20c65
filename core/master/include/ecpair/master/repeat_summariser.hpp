#pragma once
// Bounded reporting of faults that last (issue 29 item 3): a kind whose
// RepeatPolicy names a subject is reported when it starts, then summarised
// at most once per interval (how many, of which subjects, in which cycles),
// and when it ends (none for the quiet time) - as the common masters do,
// instead of a line per cycle. A fault that happened once ends silently: its
// first report said it all.
//
// offer() is the producer's side (the cycle thread, under the EventQueue's
// lock): it counts into tables sized at construction and allocates nothing.
// due() is the consumer's side: it makes the summaries and ends that are due.
// Time is a parameter of both, so every decision is tested in virtual time.

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/master/event.hpp"
#include "ecpair/master/event_report.hpp"

namespace ecpair::master {

struct RepeatOptions {
    std::chrono::nanoseconds interval = std::chrono::seconds(1);  // at most one summary per kind this often
    std::chrono::nanoseconds quiet = std::chrono::seconds(1);     // a kind not raised for this long has ended
    std::size_t kinds = 32;     // kinds in a fault at once; a kind beyond them is reported event by event
    std::size_t subjects = 8;   // subjects counted apart per kind; more are counted together as "other"
};

class RepeatSummariser {
public:
    using TimePoint = std::chrono::steady_clock::time_point;

    explicit RepeatSummariser(RepeatOptions options = {});

    // True when the event is to be reported now: a kind without a subject,
    // or the first of a fault. False: it was counted for the next report.
    bool offer(const Event& event, TimePoint now);

    // Appends the summaries and ends due at `now`; `cycle` and `time` stamp them.
    void due(TimePoint now, std::uint64_t cycle, std::chrono::system_clock::time_point time,
             std::vector<EventReport>& out);

    // When due() has something to report next, if anything is going on.
    std::optional<TimePoint> next_due() const;

private:
    struct Subject {
        std::uint64_t key = 0;
        Event last;
        std::uint64_t recent = 0;  // since the previous report
        std::uint64_t total = 0;
    };
    // One kind's fault, from its first event to the end of the quiet time.
    struct Episode {
        const EventType* type = nullptr;  // null: a free slot
        TimePoint started, last_seen, last_report;
        std::uint64_t start_cycle = 0;
        std::uint64_t first_recent_cycle = 0;
        std::uint64_t last_cycle = 0;
        std::uint64_t recent = 0;  // events since the previous report
        std::uint64_t total = 0;
        std::vector<Subject> subjects;  // capacity RepeatOptions::subjects, never exceeded
        std::uint64_t other_recent = 0;
        std::uint64_t other_total = 0;
    };

    Episode* find(const EventType* type);
    void open(Episode& episode, const Event& event, std::uint64_t key, TimePoint now);
    void count(Episode& episode, const Event& event, std::uint64_t key, TimePoint now);
    EventReport report(const Episode& episode, Repetition repetition, TimePoint now, std::uint64_t cycle,
                       std::chrono::system_clock::time_point time) const;

    RepeatOptions options_;
    std::vector<Episode> episodes_;
};

}  // namespace ecpair::master
