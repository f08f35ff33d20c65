#include "event_text.hpp"

#include <ctime>

#include <fmt/format.h>

namespace ecpair::ctl {

std::string local_time_of(std::int64_t unix_time_ms) {
    const std::time_t seconds = static_cast<std::time_t>(unix_time_ms / 1000);
    std::tm local{};
    ::localtime_r(&seconds, &local);
    return fmt::format("{:02}:{:02}:{:02}.{:03}", local.tm_hour, local.tm_min, local.tm_sec, unix_time_ms % 1000);
}

std::string event_line(const control::EventMessage& event) {
    const std::string repeat = event.repeat().empty() ? std::string() : fmt::format(" ({})", event.repeat());
    return fmt::format("{} {}{} {}", local_time_of(event.unix_time_ms()), event.kind(), repeat, event.text());
}

// A fault that repeats: the summaries' and the end's counts (the text says them too).
void write_event_json(JsonWriter& json, const control::EventMessage& event) {
    json.begin_object().key("unix_time_ms").value(event.unix_time_ms()).key("cycle").value(event.cycle());
    json.key("kind").value(event.kind()).key("text").value(event.text());
    if (!event.repeat().empty()) {
        json.key("repeat").value(event.repeat()).key("count").value(event.count()).key("total").value(event.total());
        json.key("first_cycle").value(event.first_cycle()).key("last_cycle").value(event.last_cycle());
    }
    json.end_object();
}

}  // namespace ecpair::ctl
