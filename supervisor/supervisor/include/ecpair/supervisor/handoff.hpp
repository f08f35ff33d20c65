#pragma once
// A planned switchover without a lost cycle (the ACTIVE's side).
//
//   cycle A     the ACTIVE announces in its CMF header: hand-off at cycle H
//               (H = A + lead), and keeps announcing it every cycle
//   A+1 ...     the INACTIVE, a hot standby, acknowledges in its standby
//               status (filled into the same CMF as it forwards it); the
//               ACTIVE sees the acknowledgement one cycle later: committed,
//               which its CMFs say from then on, and which is irrevocable
//   H-1         the ACTIVE's last cycle; its CMF still announces H. Not
//               committed by now: the announcement is withdrawn in this
//               CMF, the INACTIVE sees that and stays INACTIVE (cancelled)
//   H           the ACTIVE sends nothing and becomes INACTIVE; the INACTIVE,
//               which has read "committed" and runs phase-locked to the
//               ACTIVE, takes over at its boundary H (H-1's CMF arrived or
//               not) and sends cycle H in the slot where the old ACTIVE would
//               have
//
// Pure: the supervisor feeds it the cycle and the partner's answers.

#include <chrono>
#include <cstdint>
#include <optional>

#include "ecpair/supervisor/supervisor_events.hpp"
#include "ecpair/redundancy/cmf_format.hpp"

namespace ecpair::supervisor {

// Why a switchover cannot start now (nullopt: it can), from the partner's
// newest standby status and how old it is.
std::optional<HandOffRefusal> handoff_refusal(const std::optional<redundancy::CmfStandbyStatus>& partner,
                                              std::optional<std::chrono::nanoseconds> answer_age,
                                              std::chrono::nanoseconds partner_silence);

class HandOffAnnouncement {
public:
    enum class Step : std::uint8_t {
        Announce,     // keep announcing; not yet at H
        Acknowledged, // the partner acknowledged just now (keep announcing)
        StepDown,     // cycle H: send nothing, become INACTIVE
        Cancel,       // the partner did not acknowledge in time (withdraw in this cycle's CMF)
    };

    HandOffAnnouncement(std::uint64_t handoff_cycle) : cycle_(handoff_cycle) {}

    std::uint64_t cycle() const { return cycle_; }
    bool committed() const { return committed_; }
    // At the boundary of `cycle`, with the partner's newest standby status.
    Step step(std::uint64_t cycle, const std::optional<redundancy::CmfStandbyStatus>& partner);

private:
    std::uint64_t cycle_;
    bool committed_ = false;
};

}  // namespace ecpair::supervisor
