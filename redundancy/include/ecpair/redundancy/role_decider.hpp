#pragma once
// The seam between the RedundancyController, which carries out a pair
// member's role on the cycle thread, and whoever decides that role (the
// Supervisor, supervisor/). At every cycle boundary the controller says
// what it saw since the last one (PairObservation) and applies what it is
// told (RoleDecision) in that same boundary. decide() runs on the cycle
// thread: it must not block or allocate in the common case.

#include <chrono>
#include <cstdint>
#include <optional>

#include "ecpair/eni/model.hpp"
#include "ecpair/redundancy/cmf_format.hpp"

namespace ecpair::redundancy {

enum class RedState : std::uint8_t { Inactive = 0, Active = 1 };
std::string_view to_string(RedState state);

using SteadyTime = std::chrono::steady_clock::time_point;

// The header of a CMF sent by an ACTIVE master other than this one.
struct HeardActive {
    std::uint64_t cycle = 0;
    eni::SlaveState master_state = eni::SlaveState::Init;
    CmfFlags flags;
    CmfSender sender;
    bool same_fingerprint = false;  // its ENI and pair parameters are ours
    SteadyTime at{};                // when it arrived
};

struct PairObservation {
    SteadyTime now{};
    std::uint64_t cycle = 0;  // this master's cycle (counted with the partner's while INACTIVE)
    RedState role = RedState::Inactive;
    eni::SlaveState master_state = eni::SlaveState::Init;
    bool main_link_up = false;
    bool red_link_up = false;
    wire::MacAddress member;  // our MAIN adapter

    // ---- what came from another ACTIVE master
    // CMF headers of another master: any as INACTIVE, the foreign ones as ACTIVE.
    std::uint64_t headers_heard = 0;  // counts up; compare with the last value seen
    std::optional<HeardActive> heard;  // the newest
    // Complete CMFs of a partner with our fingerprint (INACTIVE: the mirror).
    std::uint64_t cmfs_completed = 0;  // counts up
    std::optional<SteadyTime> last_cmf_completed;
    bool mirror_fresh = false;         // a hot takeover is possible now
    std::uint64_t mirrored_cycle = 0;  // the ACTIVE's cycle of the newest mirrored CMF
    std::optional<std::uint64_t> acknowledged_handoff;  // the hand-off cycle this INACTIVE acknowledged

    // ---- ACTIVE: the partner's answers and other masters' frames
    std::uint64_t partner_answers = 0;  // returned CMFs the INACTIVE filled in; counts up
    std::optional<SteadyTime> partner_last_answer;
    std::optional<CmfStandbyStatus> partner_status;  // from the newest answer
    std::uint64_t foreign_frames = 0;                // frames of another master received while sending; counts up
    // Of those, the frames sent by the adapters of the ACTIVE this member
    // last followed as INACTIVE (after a hand-off: the master that handed over).
    std::uint64_t followed_master_frames = 0;
    std::uint64_t cycles_without_return = 0;         // cycles in a row none of our frames came back
    std::optional<std::uint16_t> slaves_reached;     // BRD WKC of the last complete cycle
};

struct RoleDecision {
    std::optional<RedState> role;  // change role at this boundary (a repeat of the current one does nothing)
    // ACTIVE: announce a hand-off to the partner at this cycle (flag and cycle in the CMF header).
    std::optional<std::uint64_t> handoff_cycle;
    bool handoff_committed = false;  // with handoff_cycle: the partner acknowledged, we step down at it
    // Becoming ACTIVE: the number of this cycle, when it is not our count (a
    // hand-off taken a cycle late still sends cycle H first: no number is skipped).
    std::optional<std::uint64_t> first_cycle;
    std::uint32_t epoch = 0;  // our term: in the CMF header (ACTIVE) and the standby status (INACTIVE)
    // INACTIVE: what the standby status tells the ACTIVE.
    bool ready_for_handoff = false;  // acknowledge an announced hand-off, and take over at it
    bool forced_standby = false;
    bool switchover_requested = false;
};

class RoleDecider {
public:
    virtual ~RoleDecider() = default;
    virtual RoleDecision decide(const PairObservation& seen) = 0;
};

}  // namespace ecpair::redundancy
