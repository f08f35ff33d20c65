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
    return fmt::format("{} {} {}", local_time_of(event.unix_time_ms()), event.kind(), event.text());
}

void write_event_json(JsonWriter& json, const control::EventMessage& event) {
    json.begin_object().key("unix_time_ms").value(event.unix_time_ms()).key("cycle").value(event.cycle());
    json.key("kind").value(event.kind()).key("text").value(event.text()).end_object();
}

}  // namespace ecpair::ctl
