#pragma once
// The Supervisor's events (docs/ARBITRATION.md): a pair member deciding its
// own role - the partner's silence and what this member did about it, its
// own links, frames that stop coming back after a takeover, forced standby,
// a pair without an ACTIVE member, the switchover hand-off, and the
// partner's answers in the CMF. Arbitration's events are in
// arbitration_events.hpp.

#include <cstdint>
#include <string_view>

#include "ecpair/master/event.hpp"

namespace ecpair::supervisor::events {

// a = silence in ms, b = the timeout in ms, c = SilenceAction, d = 1 if shortened by a link loss
extern const master::EventType kCommTimeout;
extern const master::EventType kAllLinksLost;        // a = 1 if this master was ACTIVE (it stepped down), 0 if INACTIVE
extern const master::EventType kLinksRestored;       // a link is back after all were lost
extern const master::EventType kFramesNotReturning;  // a = cycles in a row without any frame back, b = 1 right after a takeover
extern const master::EventType kFramesReturning;     // a = cycles it took
extern const master::EventType kStandbyForced;       // a = 1 forced, 0 released
extern const master::EventType kNoActiveMaster;      // a = NoActiveReason
extern const master::EventType kHandOff;             // a = HandOffPhase, b = the hand-off cycle (low 32 bits), c = HandOffRefusal
extern const master::EventType kPartnerLost;         // a = age of the partner's last answer in ms
extern const master::EventType kPartnerFound;        // a = ms without an answer before (0: first answer)

}  // namespace ecpair::supervisor::events

namespace ecpair::supervisor {

// What a comm timeout made this member do (events::kCommTimeout, c).
enum class SilenceAction : std::uint8_t {
    TakingOverHot,          // from the fresh mirror: no INIT, the slaves stay where they are
    TakingOverCold,         // no fresh mirror: the slaves start over from INIT
    RefusedForced,          // forced to standby: never takes over
    RefusedPartnerDiffers,  // the silent partner ran another ENI or other pair parameters
    RefusedIsolated,        // both own links are down
};

enum class HandOffPhase : std::uint8_t {
    Announced,     // ACTIVE: the hand-off is in the CMF, for cycle b
    Acknowledged,  // ACTIVE: the partner will take over at cycle b
    SteppedDown,   // ACTIVE: sent its last cycle, now INACTIVE
    TakenOver,     // INACTIVE: took over at cycle b as announced
    Cancelled,     // either side: the hand-off did not happen (c says why)
    Refused,       // not started (c says why)
};

enum class HandOffRefusal : std::uint8_t {
    None,
    PartnerNotAnswering,  // no standby status came back from the partner lately
    PartnerCold,          // the partner does not mirror this master (not fresh)
    PartnerForced,        // the partner is forced to standby
    PartnerDiffers,       // the partner runs another ENI or other pair parameters
    PartnerLinkDown,      // one of the partner's links is down
    NotAcknowledged,      // the partner did not acknowledge in time
    NotActive,            // this master is not ACTIVE and its partner did not hand off
    AlreadyRunning,       // a hand-off is under way
    PartnerLost,          // the partner went silent during the hand-off
    ForcedStandby,        // this master was forced to standby while it was to take over
};
// "the partner is forced to standby" (for events and operator replies).
std::string_view to_string(HandOffRefusal refusal);

enum class NoActiveReason : std::uint8_t {
    ForcedStandby,   // this member is forced to standby and no ACTIVE partner is heard
    PartnerDiffers,  // the only master heard runs another ENI / other parameters, and is silent now
    Isolated,        // both own links are down
};
// "both of this member's links are down" (for events and the status).
std::string_view to_string(NoActiveReason reason);

}  // namespace ecpair::supervisor
