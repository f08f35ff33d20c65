#pragma once
// The Supervisor decides a pair member's role; the RedundancyController
// carries it out (redundancy/role_decider.hpp is the seam). It is asked at
// every cycle boundary, on the cycle thread, with what the controller saw,
// and every decision it takes is an event and a log line that say why.
//
//   LISTENING   start-up, INACTIVE: the Arbiter listens for an ACTIVE's CMF
//               -> heard: STANDBY; silence: ACTIVE
//   STANDBY     INACTIVE behind an ACTIVE (hot or cold standby)
//               -> partner silent for comm_timeout (counted in our own
//                  cycles; shortened when one of our links went down and no
//                  CMF arrives on the other): ACTIVE, hot from the mirror
//                  when it is fresh; not when forced, when the partner runs
//                  another ENI/parameters, or when isolated
//               -> the ACTIVE announces a hand-off and we are ready:
//                  HANDOFF_PENDING
//   HANDOFF_PENDING  INACTIVE, acknowledged a hand-off at cycle H
//               -> mirrored cycle H-1 (our cycle is H): ACTIVE, no cycle lost
//               -> announcement withdrawn: STANDBY
//   NO_ACTIVE   INACTIVE, no ACTIVE heard, and this member may not take the
//               bus (forced standby, or the only partner differed)
//   ISOLATED    INACTIVE, both links down: never takes over
//   ACTIVE      owns the bus; watches its partner (lost / found, with the
//               age of its last answer) and whether its frames come back
//               -> both links down: INACTIVE, ISOLATED
//               -> another master sends too (foreign source MAC in a few
//                  cycles running, or its CMF): BACKING_OFF; after a
//                  hand-off, the last cycles of the master that handed over
//                  (sent late, before its H) are not counted
//               -> switchover asked (here, by the partner, or by forcing
//                  this member to standby) and the partner is a hot
//                  standby: HANDING_OVER
//   HANDING_OVER  ACTIVE, announcing the hand-off (handoff.hpp)
//               -> cycle H: INACTIVE, STANDBY; not acknowledged: ACTIVE
//   BACKING_OFF INACTIVE after a collision: the Arbiter's backoff
//               -> an ACTIVE heard: STANDBY; silence: ACTIVE
//
// A member forced to standby never becomes ACTIVE, by timeout or by
// arbitration, until it is released. Operator commands (any thread) take
// effect at the next boundary; switchover() answers at once when the partner
// is plainly no hot standby.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "ecpair/arbitration/arbiter.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/redundancy/role_decider.hpp"
#include "ecpair/supervisor/comm_timeout.hpp"
#include "ecpair/supervisor/handoff.hpp"
#include "ecpair/supervisor/supervisor_events.hpp"

namespace ecpair::supervisor {

struct SupervisorOptions {
    std::chrono::nanoseconds cycle_time{std::chrono::milliseconds(1)};
    std::chrono::nanoseconds comm_timeout{std::chrono::milliseconds(50)};
    // After a link of ours went down: how long a CMF on the other link is awaited (0: 3 cycles).
    std::chrono::nanoseconds link_loss_confirm{0};
    // ACTIVE: the partner is lost after this long without an answer in the CMF.
    std::chrono::nanoseconds partner_silence{std::chrono::milliseconds(100)};
    // ACTIVE: cycles in a row without any frame back before that is reported.
    std::uint32_t no_return_cycles = 20;
    // ACTIVE: foreign frames in this many cycles running are a collision.
    std::uint32_t collision_cycles = 3;
    // A hand-off is announced this many cycles ahead: time for the partner's
    // acknowledgement to come back and for several CMFs to say "committed"
    // before H (with 4, one late return left only H-1's CMF to say it).
    std::uint32_t handoff_lead_cycles = 8;
    bool start_in_forced_standby = false;
    // Take over from a silent partner whose ENI or pair parameters differ (it
    // would drive the bus with another configuration): off unless asked for.
    bool takeover_from_differing_partner = false;
    // Start-up: take the bus at once instead of listening (commissioning, tests).
    bool start_active = false;
    arbitration::ArbiterOptions arbitration;
};

enum class SupervisorState : std::uint8_t {
    Listening,
    Standby,
    HandOffPending,
    NoActive,
    Isolated,
    Active,
    HandingOver,
    BackingOff,
};
std::string_view to_string(SupervisorState state);

struct SupervisorCounters {
    std::uint64_t takeovers = 0;  // became ACTIVE (any reason)
    std::uint64_t comm_timeouts = 0;
    std::uint64_t collisions = 0;
    std::uint64_t backoffs_won = 0;   // took the bus after a backoff
    std::uint64_t backoffs_lost = 0;  // yielded after a backoff
    std::uint64_t handoffs = 0;       // completed, either side
    std::uint64_t handoffs_cancelled = 0;
    std::uint64_t partner_lost = 0;
};

struct SupervisorStatus {
    SupervisorState state = SupervisorState::Listening;
    std::string why;  // the reason of the last transition, for operators
    redundancy::RedState role = redundancy::RedState::Inactive;
    bool forced_standby = false;
    bool hot_standby = false;  // INACTIVE: mirrors a partner with our fingerprint, fresh
    std::uint32_t epoch = 0;
    arbitration::ArbiterState arbitration = arbitration::ArbiterState::Idle;
    std::chrono::nanoseconds comm_timeout{0};
    std::chrono::nanoseconds silence{0};  // INACTIVE: counted towards the comm timeout
    std::chrono::nanoseconds longest_silence{0};  // the longest silence counted standing by, since start
    std::optional<std::uint64_t> handoff_cycle;
    std::optional<NoActiveReason> no_active;  // set while no member can be ACTIVE as far as we know
    std::optional<HandOffRefusal> handoff_refusal;  // ACTIVE: why a switchover could not start now
    SupervisorCounters counters;
};

class Supervisor final : public redundancy::RoleDecider {
public:
    Supervisor(const SupervisorOptions& options, arbitration::RandomSource& random, master::EventQueue& events);

    // ---- cycle thread (RoleDecider)
    redundancy::RoleDecision decide(const redundancy::PairObservation& seen) override;

    // ---- any thread: operator commands, applied at the next boundary
    // A zero-loss hand-off to the partner (on the ACTIVE) or a request for one
    // (on the INACTIVE). The error says why not, when that is known now.
    Expected<void, std::string> switchover();
    void force_standby(bool forced);
    // Expert override (ecpairctl red-state): take the bus / step down now, without a hand-off.
    void request_role(redundancy::RedState role);

    SupervisorStatus status() const;

private:
    using Observation = redundancy::PairObservation;
    using SteadyTime = redundancy::SteadyTime;

    void transition(SupervisorState to, std::string why);
    void raise(master::EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0,
               std::uint32_t d = 0);
    arbitration::Contender ours(const Observation& seen) const;
    std::optional<arbitration::Contender> theirs(const Observation& seen) const;
    void take_bus(const Observation& seen, std::string why);
    void step_down(SupervisorState to, std::string why);
    void step_down_forced(std::string_view why);

    void on_listening(const Observation& seen);
    void on_standby(const Observation& seen);
    void on_handoff_pending(const Observation& seen);
    void on_no_active(const Observation& seen);
    void on_isolated(const Observation& seen);
    void on_active(const Observation& seen);
    void on_handing_over(const Observation& seen);
    void on_backing_off(const Observation& seen);

    void watch_links(const Observation& seen);
    void watch_partner(const Observation& seen);
    void watch_returns(const Observation& seen);
    bool collision_seen(const Observation& seen);
    bool previous_active_finishing(const Observation& seen);
    void partner_silent(const Observation& seen);
    std::optional<HandOffRefusal> refusal(const Observation& seen) const;
    void start_handoff(const Observation& seen);
    bool heard_new_active(const Observation& seen) const;
    bool may_take_bus(const Observation& seen) const;
    void publish(const Observation& seen, const redundancy::RoleDecision& decision);

    SupervisorOptions options_;
    master::EventQueue& events_;
    arbitration::Arbiter arbiter_;
    CommTimeout comm_;
    std::chrono::nanoseconds longest_standby_silence_{0};

    // Cycle thread.
    bool started_ = false;
    SupervisorState state_ = SupervisorState::Listening;
    std::string why_ = "starting";
    std::uint64_t cycle_ = 0;
    std::uint32_t epoch_ = 0;  // ours, or the newest heard while standby
    std::optional<redundancy::RedState> role_;  // the role to ask for at this boundary
    bool forced_ = false;
    bool links_up_[2] = {true, true};
    std::uint64_t headers_seen_ = 0;
    std::uint64_t cmfs_seen_ = 0;
    std::uint64_t answers_seen_ = 0;
    std::uint64_t foreign_seen_ = 0;
    std::uint64_t followed_frames_seen_ = 0;
    std::uint32_t foreign_cycles_ = 0;
    // ACTIVE after taking a hand-off at H: the master that handed over may
    // still be sending its last cycles (before H) when it ran late.
    struct HandedOver {
        std::uint64_t cycle = 0;                // H
        SteadyTime at{};                        // our boundary H
        std::optional<SteadyTime> answered_at;  // its first answer as our standby
        bool reported = false;                  // its late frames logged
    };
    std::optional<HandedOver> handed_over_;
    bool partner_seen_ = false;
    bool returns_reported_ = false;
    std::uint64_t takeover_cycle_ = 0;  // when this master last became ACTIVE after a partner's failure
    std::optional<HandOffAnnouncement> announcement_;
    std::optional<std::uint64_t> pending_handoff_;  // INACTIVE: acknowledged hand-off cycle
    bool handoff_committed_ = false;                // INACTIVE: a CMF said the ACTIVE committed to it
    std::optional<std::uint64_t> first_cycle_;      // taking a hand-off late: number this cycle H
    bool switchover_requested_ = false;  // INACTIVE: asking the ACTIVE in the standby status
    std::uint64_t switchover_until_ = 0;
    bool partner_asked_ = false;  // ACTIVE: the partner's last standby status asked for a switchover
    std::optional<SteadyTime> partner_lost_at_;  // the partner's last answer when it was called lost
    std::optional<NoActiveReason> no_active_;
    SupervisorCounters counters_;

    // Operator requests (any thread -> cycle thread).
    std::atomic<bool> switchover_request_{false};
    std::atomic<int> force_request_{-1};  // -1 none, 0 release, 1 force
    std::atomic<int> role_request_{-1};   // -1 none, else RedState

    mutable std::mutex status_mutex_;
    SupervisorStatus status_;
};

}  // namespace ecpair::supervisor
