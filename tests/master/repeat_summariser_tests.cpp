// Bounded logs under persistent faults (issue 29 item 3), in virtual time:
// a kind that repeats every cycle is reported when it starts, summarised at
// most once a second with counts per subject, and when it ends; the counts
// add up to every event raised.

#include <catch2/catch.hpp>

#include <fmt/format.h>

#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/master/repeat_summariser.hpp"

using namespace ecpair::master;
using namespace std::chrono_literals;

namespace {

using TimePoint = RepeatSummariser::TimePoint;

std::string describe_test(const Event& e, const EventDescriber&) { return fmt::format("test {} {}", e.a, e.b); }
std::uint64_t subject_a(const Event& e) { return e.a; }

constinit const EventType kRepeating{"test-repeating", describe_test, {subject_a}};
constinit const EventType kOther{"test-other-repeating", describe_test, {subject_a}};
constinit const EventType kOnce{"test-once", describe_test};

Event event(const EventType& type, std::uint64_t cycle, std::uint32_t a = 0, std::uint32_t b = 0) {
    return Event{type, cycle, std::chrono::system_clock::time_point{}, a, b, 0, 0};
}

// Everything due at `now`.
std::vector<EventReport> due(RepeatSummariser& s, TimePoint now, std::uint64_t cycle) {
    std::vector<EventReport> out;
    s.due(now, cycle, std::chrono::system_clock::time_point{}, out);
    return out;
}

const TimePoint t0{};

}  // namespace

TEST_CASE("a kind without a subject is reported every time") {
    RepeatSummariser s;
    for (std::uint64_t cycle = 1; cycle <= 5; ++cycle) CHECK(s.offer(event(kOnce, cycle), t0 + cycle * 1ms));
    CHECK(due(s, t0 + 10s, 10).empty());
    CHECK_FALSE(s.next_due());
}

TEST_CASE("a fault raised every cycle for 10 s: its start, a summary a second, its end, and the counts add up") {
    RepeatSummariser s;  // 1 s interval, 1 s quiet
    std::vector<EventReport> reports;
    std::uint64_t offered = 0;
    std::uint64_t reported_now = 0;
    // 1 ms cycles, cycles 1..10000; two datagrams (subjects 3 and 5) fail every cycle.
    for (std::uint64_t cycle = 1; cycle <= 10000; ++cycle) {
        const TimePoint now = t0 + cycle * 1ms;
        for (std::uint32_t datagram : {3u, 5u}) {
            ++offered;
            if (s.offer(event(kRepeating, cycle, datagram, static_cast<std::uint32_t>(cycle)), now)) ++reported_now;
        }
        if (cycle % 200 == 0) {  // the consumer looks five times a second
            for (auto& r : due(s, now, cycle)) reports.push_back(std::move(r));
        }
    }
    CHECK(reported_now == 1);  // the first event only
    // The fault stopped at cycle 10000: it ends once it was quiet for a second.
    for (auto& r : due(s, t0 + 10000ms + 999ms, 10999)) reports.push_back(std::move(r));
    REQUIRE(reports.back().repetition == Repetition::Summary);
    for (auto& r : due(s, t0 + 11000ms, 11000)) reports.push_back(std::move(r));
    REQUIRE(reports.back().repetition == Repetition::End);

    std::uint64_t summaries = 0;
    std::uint64_t counted = 1;  // the first event, reported as it was
    for (const auto& r : reports) {
        counted += r.count;
        if (r.repetition == Repetition::Summary) {
            ++summaries;
            CHECK(r.span >= 1s);  // at most one a second
            REQUIRE(r.subjects.size() == 2);
            CHECK(r.subjects[0].last.a == 3);
            CHECK(r.subjects[1].last.a == 5);
            CHECK(r.subjects[0].last.b == r.last_cycle);  // the subject's latest event
            CHECK(r.first_cycle <= r.last_cycle);
        }
    }
    CHECK(summaries == 10);  // at 1.2 s, 2.2 s ... 9.2 s (looked at every 200 ms), and 11.0 s
    const EventReport& end = reports.back();
    CHECK(end.total == offered);
    CHECK(counted == offered);
    CHECK(end.start_cycle == 1);
    CHECK(end.first_cycle == 1);
    CHECK(end.last_cycle == 10000);
    CHECK(end.event.cycle == 11000);  // when the end was seen
    CHECK(end.span == 9999ms);
    REQUIRE(end.subjects.size() == 2);
    CHECK(end.subjects[0].count == 10000);  // totals per subject
    CHECK(end.subjects[1].count == 10000);
    CHECK(end.event.kind == kRepeating);
    CHECK_FALSE(s.next_due());
}

TEST_CASE("a fault that happened once ends without another line") {
    RepeatSummariser s;
    CHECK(s.offer(event(kRepeating, 7, 1), t0));
    REQUIRE(s.next_due());
    CHECK(*s.next_due() == t0 + 1s);
    CHECK(due(s, t0 + 1s, 1007).empty());
    CHECK_FALSE(s.next_due());
    // The next one starts a new fault, reported as it is.
    CHECK(s.offer(event(kRepeating, 2000, 1), t0 + 2s));
}

TEST_CASE("no summary for a second without events: the end says the rest") {
    RepeatSummariser s;
    CHECK(s.offer(event(kRepeating, 1, 1), t0));
    CHECK_FALSE(s.offer(event(kRepeating, 2, 1), t0 + 1ms));
    CHECK_FALSE(s.offer(event(kRepeating, 3, 1), t0 + 2ms));
    // Not yet a second since the start: nothing due, the next look is at the interval.
    CHECK(due(s, t0 + 500ms, 500).empty());
    REQUIRE(s.next_due());
    CHECK(*s.next_due() == t0 + 1s);
    // Looked at late (after the quiet time): only the end, with both events.
    const auto reports = due(s, t0 + 1500ms, 1500);
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].repetition == Repetition::End);
    CHECK(reports[0].count == 2);
    CHECK(reports[0].total == 3);
    CHECK(reports[0].last_cycle == 3);
}

TEST_CASE("an intermittent fault stays one fault while it comes back within the quiet time") {
    RepeatSummariser s;
    std::uint64_t reported_now = 0;
    std::vector<EventReport> reports;
    for (int i = 0; i < 20; ++i) {  // every 600 ms for 12 s
        const TimePoint now = t0 + i * 600ms;
        if (s.offer(event(kRepeating, static_cast<std::uint64_t>(i), 1), now)) ++reported_now;
        for (auto& r : due(s, now + 300ms, 0)) reports.push_back(std::move(r));
    }
    CHECK(reported_now == 1);
    for (const auto& r : reports) CHECK(r.repetition == Repetition::Summary);
    CHECK(reports.size() <= 12);
}

TEST_CASE("kinds are summarised apart, and subjects beyond the table are counted as others") {
    RepeatOptions options;
    options.subjects = 2;
    RepeatSummariser s(options);
    CHECK(s.offer(event(kRepeating, 1, 1), t0));
    CHECK(s.offer(event(kOther, 1, 9), t0));  // another kind: a fault of its own
    for (std::uint32_t subject = 1; subject <= 4; ++subject) CHECK_FALSE(s.offer(event(kRepeating, 2, subject), t0 + 1ms));
    const auto reports = due(s, t0 + 1s, 1000);
    REQUIRE(reports.size() == 1);  // kOther had nothing since its start
    const auto& r = reports[0];
    CHECK(r.event.kind == kRepeating);
    CHECK(r.count == 4);
    REQUIRE(r.subjects.size() == 2);
    CHECK(r.subjects[0].last.a == 1);
    CHECK(r.subjects[0].count == 1);
    CHECK(r.subjects[1].last.a == 2);
    CHECK(r.other == 2);  // subjects 3 and 4
}

TEST_CASE("with more kinds in a fault than the table holds, the rest are reported event by event") {
    RepeatOptions options;
    options.kinds = 1;
    RepeatSummariser s(options);
    CHECK(s.offer(event(kRepeating, 1, 1), t0));
    CHECK_FALSE(s.offer(event(kRepeating, 2, 1), t0));
    CHECK(s.offer(event(kOther, 2, 1), t0));
    CHECK(s.offer(event(kOther, 3, 1), t0));
}

TEST_CASE("the queue counts repeats instead of queueing them, and reports summaries when due") {
    TimePoint now = t0;
    EventQueueOptions options;
    options.capacity = 4;  // a flood would overflow it
    options.clock = [&now] { return now; };
    EventQueue queue(options);
    std::atomic<std::uint64_t> cycle{0};
    queue.attach_cycle_counter(&cycle);
    std::uint64_t reported = 0;
    std::uint64_t lines = 0;
    for (int i = 1; i <= 3000; ++i) {  // 3 s of a WKC error every cycle
        now = t0 + i * 1ms;
        cycle = static_cast<std::uint64_t>(i);
        queue.push(Event{events::kCyclicWkcError, cycle.load(), std::chrono::system_clock::now(), 0, 1, 3, 0});
        if (i % 100 == 0) {
            for (const auto& r : queue.pop_all(0ms)) {
                ++lines;
                reported += r.count;
            }
        }
    }
    now += 1s;
    cycle = 4000;
    const auto last = queue.pop_all(0ms);
    REQUIRE(last.size() == 1);
    CHECK(last[0].repetition == Repetition::End);
    CHECK(last[0].event.cycle == 4000);
    CHECK(last[0].total == 3000);
    reported += last[0].count;
    CHECK(reported == 3000);
    CHECK(lines == 3);  // the start, the summaries at 1.1 s and 2.1 s (then the end)
    CHECK(queue.dropped() == 0);
    queue.attach_cycle_counter(nullptr);
}

TEST_CASE("a full queue drops and counts events that are reported one by one") {
    EventQueueOptions options;
    options.capacity = 2;
    EventQueue queue(options);
    for (int i = 0; i < 5; ++i) queue.raise(events::kSlavePresence, 1, 1);
    CHECK(queue.dropped() == 3);
    CHECK(queue.pop_all(0ms).size() == 2);
}

TEST_CASE("events raised outside the cycle thread carry the master's current cycle") {
    EventQueue queue;
    queue.raise(events::kLinkDown);
    std::atomic<std::uint64_t> cycle{123456};
    queue.attach_cycle_counter(&cycle);
    queue.raise(events::kTopologyChangeDetected, 1);
    cycle = 123457;
    queue.raise(events::kSlavePresence, 2, 0);
    queue.attach_cycle_counter(nullptr);
    const auto reports = queue.pop_all(std::chrono::milliseconds(0));
    REQUIRE(reports.size() == 3);
    CHECK(reports[0].event.cycle == 0);  // no master attached
    CHECK(reports[1].event.cycle == 123456);
    CHECK(reports[2].event.cycle == 123457);
    CHECK(reports[2].repetition == Repetition::Single);
    CHECK(reports[2].count == 1);
}

TEST_CASE("a slave that keeps sending a CoE emergency is one fault, its code and slave counted apart") {
    REQUIRE(events::kCoeEmergency.repeat.summarised());
    const auto subject = events::kCoeEmergency.repeat.subject;
    const auto emergency = [](std::uint64_t cycle, std::uint32_t slave, std::uint32_t code, std::uint32_t reg) {
        return event(events::kCoeEmergency, cycle, slave, code | reg << 16);
    };
    CHECK(subject(emergency(1, 2, 0x8130, 0x11)) == subject(emergency(2, 2, 0x8130, 0x01)));  // the register may move
    CHECK(subject(emergency(1, 2, 0x8130, 0x11)) != subject(emergency(1, 3, 0x8130, 0x11)));
    CHECK(subject(emergency(1, 2, 0x8130, 0x11)) != subject(emergency(1, 2, 0x8110, 0x11)));

    // Every 10 ms poll finds it again for a second: the first is reported, the rest are one summary.
    RepeatSummariser s;
    CHECK(s.offer(emergency(10, 2, 0x8130, 0x11), t0));
    for (std::uint64_t k = 1; k < 100; ++k) CHECK_FALSE(s.offer(emergency(10 + 10 * k, 2, 0x8130, 0x11), t0 + k * 10ms));
    CHECK_FALSE(s.offer(emergency(1000, 3, 0x8110, 0), t0 + 995ms));
    const auto summary = due(s, t0 + 1s, 1000);
    REQUIRE(summary.size() == 1);
    CHECK(summary[0].repetition == Repetition::Summary);
    CHECK(summary[0].count == 100);
    REQUIRE(summary[0].subjects.size() == 2);
    CHECK(summary[0].subjects[0].count == 99);
    CHECK(summary[0].subjects[1].last.a == 3);
}
