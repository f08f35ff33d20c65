#pragma once
// The event mechanism every layer raises its events through (design.md §5).
// An event is a small value: a kind, the cycle, the time and four numbers,
// so that the cycle thread can raise it without allocating. Text is made on
// the consumer's side.
//
// A kind is an EventType that the layer owning it defines in its own folder
// (the master's in master_events.hpp, the redundancy's in
// redundancy_events.hpp, ...): its name as operators, scripts and tests see
// it ("cyclic-wkc-error"), how to describe one from its numbers, and its
// repeat policy. Nothing here knows the kinds: the queue, the describer and
// the daemon's operator service read all of them through their EventType.
//
// Adding a kind: in the layer's `*_events.hpp`, declare
//     extern const master::EventType kSomethingHappened;  // a = ..., b = ...
// and in its .cpp define it with constinit, a name and a describe function
// that says what happened, to what, and what ecpair did about it; raise it
// with EventQueue::raise or push. A kind that can repeat every cycle or
// frame while a fault lasts gets a RepeatPolicy (event_queue.hpp says what
// that does to the log).

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>

namespace ecpair::master {

struct Event;
class EventDescriber;

// How a kind repeats. A kind that may be raised every cycle or frame while
// a fault lasts (a WKC error, a lost frame) names its subject: which of its
// events belong together (the same datagram, the same link). Such a kind is
// reported when it starts, summarised at most once a second with counts
// per subject, and when it ends (EventQueue, RepeatSummariser).
struct RepeatPolicy {
    // Null: every event of the kind is reported as it is.
    std::uint64_t (*subject)(const Event& event) = nullptr;

    bool summarised() const { return subject != nullptr; }
};

struct EventType {
    std::string_view name;  // kebab-case, stable: operators, scripts and tests use it
    // What the numbers say, without the "cycle N: " that EventDescriber puts
    // in front; the describer names slaves, frames and datagrams from the ENI
    // and the cyclic plan.
    std::string (*describe)(const Event& event, const EventDescriber& describer) = nullptr;
    RepeatPolicy repeat{};
};

// Which kind an event is: a reference to the EventType of its owner.
class EventKind {
public:
    EventKind();  // an event nobody set a kind for (reads as "unspecified-event")
    constexpr EventKind(const EventType& type) : type_(&type) {}  // NOLINT: a kind is its type

    const EventType& type() const { return *type_; }
    std::string_view name() const { return type_->name; }

    friend bool operator==(const EventKind&, const EventKind&) = default;

private:
    const EventType* type_;
};

std::ostream& operator<<(std::ostream& out, const EventKind& kind);  // its name
std::string_view to_string(const EventKind& kind);

struct Event {
    EventKind kind;
    std::uint64_t cycle = 0;
    std::chrono::system_clock::time_point time;
    std::uint32_t a = 0, b = 0, c = 0, d = 0;
};

}  // namespace ecpair::master
