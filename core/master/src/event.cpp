#include "ecpair/master/event.hpp"

#include <ostream>

#include <fmt/format.h>

#include "ecpair/master/event_report.hpp"

namespace ecpair::master {
namespace {

std::string describe_unspecified(const Event& e, const EventDescriber&) {
    return fmt::format("an event without a kind (a = {}, b = {}, c = {}, d = {})", e.a, e.b, e.c, e.d);
}

constinit const EventType kUnspecified{"unspecified-event", describe_unspecified};

}  // namespace

EventKind::EventKind() : type_(&kUnspecified) {}

std::ostream& operator<<(std::ostream& out, const EventKind& kind) { return out << kind.name(); }

std::string_view to_string(const EventKind& kind) { return kind.name(); }

std::string_view to_string(Repetition repetition) {
    switch (repetition) {
        case Repetition::Single: return "";
        case Repetition::Summary: return "summary";
        case Repetition::End: return "end";
    }
    return "";
}

}  // namespace ecpair::master
