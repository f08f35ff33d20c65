// An episode is one kind's fault: it opens with the kind's first event
// (reported as it is), counts every later event under its subject, reports a
// summary when events came since the previous report and the interval has
// passed, and closes when the kind was quiet for the quiet time (reported
// as the end, unless the first event was the only one).

#include "ecpair/master/repeat_summariser.hpp"

#include <algorithm>

namespace ecpair::master {

RepeatSummariser::RepeatSummariser(RepeatOptions options) : options_(options), episodes_(options.kinds) {
    for (auto& episode : episodes_) episode.subjects.reserve(options_.subjects);
}

RepeatSummariser::Episode* RepeatSummariser::find(const EventType* type) {
    for (auto& episode : episodes_) {
        if (episode.type == type) return &episode;
    }
    return nullptr;
}

bool RepeatSummariser::offer(const Event& event, TimePoint now) {
    const EventType& type = event.kind.type();
    if (!type.repeat.summarised()) return true;
    const std::uint64_t key = type.repeat.subject(event);
    if (Episode* episode = find(&type)) {
        count(*episode, event, key, now);
        return false;
    }
    Episode* free = find(nullptr);
    if (free == nullptr) return true;  // more kinds in a fault at once than the table holds
    open(*free, event, key, now);
    return true;
}

void RepeatSummariser::open(Episode& episode, const Event& event, std::uint64_t key, TimePoint now) {
    episode.type = &event.kind.type();
    episode.started = episode.last_seen = episode.last_report = now;
    episode.start_cycle = episode.first_recent_cycle = episode.last_cycle = event.cycle;
    episode.recent = 0;  // the first event is reported as it is
    episode.total = 1;
    episode.subjects.clear();
    episode.subjects.push_back(Subject{key, event, 0, 1});
    episode.other_recent = episode.other_total = 0;
}

void RepeatSummariser::count(Episode& episode, const Event& event, std::uint64_t key, TimePoint now) {
    episode.last_seen = now;
    if (episode.recent == 0) episode.first_recent_cycle = event.cycle;
    episode.last_cycle = event.cycle;
    ++episode.recent;
    ++episode.total;
    const auto subject = std::find_if(episode.subjects.begin(), episode.subjects.end(),
                                      [key](const Subject& s) { return s.key == key; });
    if (subject != episode.subjects.end()) {
        subject->last = event;
        ++subject->recent;
        ++subject->total;
    } else if (episode.subjects.size() < options_.subjects) {
        episode.subjects.push_back(Subject{key, event, 1, 1});  // within the reserved capacity
    } else {
        ++episode.other_recent;
        ++episode.other_total;
    }
}

EventReport RepeatSummariser::report(const Episode& episode, Repetition repetition, TimePoint now,
                                     std::uint64_t cycle, std::chrono::system_clock::time_point time) const {
    const bool end = repetition == Repetition::End;
    EventReport r;
    r.repetition = repetition;
    r.count = episode.recent;
    r.total = episode.total;
    r.start_cycle = episode.start_cycle;
    r.first_cycle = end ? episode.start_cycle : episode.first_recent_cycle;
    r.last_cycle = episode.last_cycle;
    r.span = end ? episode.last_seen - episode.started : now - episode.last_report;
    for (const Subject& s : episode.subjects) {
        const std::uint64_t n = end ? s.total : s.recent;
        if (n > 0) r.subjects.push_back(SubjectCount{s.last, n});
    }
    r.other = end ? episode.other_total : episode.other_recent;
    r.event = episode.subjects.front().last;
    r.event.cycle = cycle;
    r.event.time = time;
    return r;
}

void RepeatSummariser::due(TimePoint now, std::uint64_t cycle, std::chrono::system_clock::time_point time,
                           std::vector<EventReport>& out) {
    for (Episode& episode : episodes_) {
        if (episode.type == nullptr) continue;
        if (now - episode.last_seen >= options_.quiet) {
            if (episode.total > 1) out.push_back(report(episode, Repetition::End, now, cycle, time));
            episode.type = nullptr;
            continue;
        }
        if (episode.recent > 0 && now - episode.last_report >= options_.interval) {
            out.push_back(report(episode, Repetition::Summary, now, cycle, time));
            episode.last_report = now;
            episode.recent = 0;
            episode.other_recent = 0;
            for (Subject& s : episode.subjects) s.recent = 0;
        }
    }
}

std::optional<RepeatSummariser::TimePoint> RepeatSummariser::next_due() const {
    std::optional<TimePoint> next;
    const auto earlier = [&next](TimePoint t) { next = next ? std::min(*next, t) : t; };
    for (const Episode& episode : episodes_) {
        if (episode.type == nullptr) continue;
        earlier(episode.last_seen + options_.quiet);
        if (episode.recent > 0) earlier(episode.last_report + options_.interval);
    }
    return next;
}

}  // namespace ecpair::master
