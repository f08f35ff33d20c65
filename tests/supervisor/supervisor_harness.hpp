#pragma once
// Drives a Supervisor cycle by cycle in virtual time. The test sets what the
// RedundancyController would have seen (an ACTIVE's CMF heard, the mirror,
// the partner's answers, foreign frames, links) and calls cycle(); the
// harness keeps the observation's counters and the role the Supervisor asked
// for, as the controller would, and collects the events.

#include <algorithm>
#include <chrono>
#include <vector>

#include "ecpair/arbitration/arbitration_events.hpp"
#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/redundancy/redundancy_events.hpp"
#include "ecpair/supervisor/supervisor_events.hpp"
#include "ecpair/supervisor/supervisor.hpp"
#include "../arbitration/scripted_random.hpp"

namespace ecpair::test {

class SupervisorHarness {
public:
    using RedState = redundancy::RedState;

    static supervisor::SupervisorOptions default_options() {
        supervisor::SupervisorOptions o;
        o.cycle_time = std::chrono::milliseconds(1);
        o.comm_timeout = std::chrono::milliseconds(50);
        o.partner_silence = std::chrono::milliseconds(100);
        o.arbitration.listen_time = std::chrono::milliseconds(200);
        o.arbitration.backoff_min = std::chrono::milliseconds(1);
        o.arbitration.backoff_max = std::chrono::milliseconds(10);
        return o;
    }

    explicit SupervisorHarness(supervisor::SupervisorOptions options = default_options(),
                               std::vector<double> draws = {0.5})
        : random(std::move(draws)), supervisor(options, random, events) {
        seen.now = redundancy::SteadyTime(std::chrono::seconds(100));
        seen.main_link_up = true;
        seen.red_link_up = true;
        seen.member = wire::MacAddress{{0x02, 0, 0, 0, 0, 0x11}};
        seen.cycle = 1;
    }

    // One cycle boundary: 1 ms later (or `gap`), the decision applied.
    redundancy::RoleDecision cycle(std::chrono::nanoseconds gap = std::chrono::milliseconds(1)) {
        seen.now += gap;
        ++seen.cycle;
        last = supervisor.decide(seen);
        if (last.role) seen.role = *last.role;
        for (const auto& r : events.pop_all(std::chrono::milliseconds(0))) got.push_back(r.event);
        return last;
    }
    void cycles(int n) {
        for (int i = 0; i < n; ++i) cycle();
    }
    // Runs cycles until `done` holds (at most `limit`); how many it took.
    template <class Done>
    int until(Done done, int limit = 10'000) {
        for (int i = 1; i <= limit; ++i) {
            cycle();
            if (done()) return i;
        }
        return -1;
    }

    // ---- what the controller would have seen since the last cycle
    // A CMF of an ACTIVE partner arrived and completed (and was mirrored).
    void partner_cmf(bool same_fingerprint = true, std::uint32_t epoch = 1) {
        ++seen.headers_heard;
        redundancy::HeardActive h;
        h.cycle = seen.cycle;
        h.same_fingerprint = same_fingerprint;
        h.sender.epoch = epoch;
        h.sender.slaves_reached = partner_reach;
        h.sender.member = wire::MacAddress{{0x02, 0, 0, 0, 0, 0x21}};
        h.at = seen.now;
        h.flags.handoff_request = announced_handoff.has_value();
        h.sender.handoff_cycle = announced_handoff.value_or(0);
        h.flags.handoff_committed = announced_handoff.has_value() && announced_committed;
        seen.heard = h;
        if (same_fingerprint) {
            ++seen.cmfs_completed;
            seen.last_cmf_completed = seen.now;
            seen.mirror_fresh = true;
            seen.mirrored_cycle = seen.cycle;
            // The controller acknowledges an announced hand-off when the supervisor is ready.
            if (announced_handoff && last.ready_for_handoff) seen.acknowledged_handoff = announced_handoff;
        }
    }
    // The INACTIVE partner answered in the CMF we sent.
    void partner_answer(bool hot = true, bool forced = false, bool acknowledged = false) {
        ++seen.partner_answers;
        seen.partner_last_answer = seen.now;
        redundancy::CmfStandbyStatus s;
        s.hot = hot;
        s.forced = forced;
        s.main_link_up = true;
        s.red_link_up = true;
        s.member = wire::MacAddress{{0x02, 0, 0, 0, 0, 0x21}};
        s.handoff_acknowledged = acknowledged;
        s.handoff_cycle_low = acknowledged && last.handoff_cycle ? static_cast<std::uint32_t>(*last.handoff_cycle) : 0;
        seen.partner_status = s;
    }
    // Another master's frames arrived; `from_followed`: sent by the ACTIVE
    // this member followed before (the controller knows its adapters).
    void foreign_frames(bool from_followed = false) {
        ++seen.foreign_frames;
        if (from_followed) ++seen.followed_master_frames;
    }

    bool raised(master::EventKind kind) const {
        return std::any_of(got.begin(), got.end(), [kind](const master::Event& e) { return e.kind == kind; });
    }
    const master::Event* find(master::EventKind kind) const {
        for (const auto& e : got) {
            if (e.kind == kind) return &e;
        }
        return nullptr;
    }
    supervisor::SupervisorState state() const { return supervisor.status().state; }
    bool active() const { return seen.role == RedState::Active; }

    ScriptedRandom random;
    master::EventQueue events;
    supervisor::Supervisor supervisor;
    redundancy::PairObservation seen;
    redundancy::RoleDecision last;
    std::vector<master::Event> got;
    std::optional<std::uint64_t> announced_handoff;  // what the partner's CMF header announces
    bool announced_committed = false;                // ... and whether it says it committed to it
    std::uint16_t partner_reach = 5;
};

}  // namespace ecpair::test
