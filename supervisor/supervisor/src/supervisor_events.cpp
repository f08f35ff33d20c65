// The Supervisor's event texts: what the member saw (the partner's silence,
// its own links, frames not coming back) and what it did about it (took
// over hot or cold, refused to, stepped down, handed off).

#include "ecpair/supervisor/supervisor_events.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecpair::supervisor {
namespace {

using master::Event;
using master::EventDescriber;

std::string comm_timeout(const Event& e, const EventDescriber&) {
    static constexpr const char* kAction[] = {
        "taking over hot from the mirror (no INIT, the slaves stay in their state)",
        "taking over cold (no fresh mirror: the slaves start over from INIT)",
        "NOT taking over: this member is forced to standby",
        "NOT taking over: the partner ran another ENI or other pair parameters",
        "NOT taking over: both own links are down (isolated)"};
    return fmt::format("no Cyclic Master Red Frame from the ACTIVE partner for {} ms (comm timeout {} ms{}): {}", e.a,
                       e.b, e.d != 0 ? ", shortened because a link went down" : "",
                       kAction[std::min<std::uint32_t>(e.c, 4)]);
}

std::string all_links_lost(const Event& e, const EventDescriber&) {
    return e.a != 0 ? "all links lost (MAIN and RED down): this ACTIVE master becomes INACTIVE, its partner may take over"
                    : "all links lost (MAIN and RED down): isolated, will not take over";
}

std::string links_restored(const Event&, const EventDescriber&) {
    return "a link is back: listening for an ACTIVE master again";
}

std::string frames_not_returning(const Event& e, const EventDescriber&) {
    return fmt::format("none of this master's frames came back on MAIN or RED for {} cycles: the ring is open at both "
                       "ends{}; still sending",
                       e.a,
                       e.b != 0 ? " - most likely the failed partner's links are still up and swallow the frames (its "
                                  "link guard did not take them down: pull its cables)"
                                : " (both cables, or a partner that swallows the frames)");
}

std::string frames_returning(const Event& e, const EventDescriber&) {
    return fmt::format("frames come back again, after {} cycles", e.a);
}

std::string standby_forced(const Event& e, const EventDescriber&) {
    return e.a != 0 ? "forced to standby: this master will not become ACTIVE"
                    : "standby no longer forced: this master may become ACTIVE";
}

std::string no_active_master(const Event& e, const EventDescriber&) {
    const auto reason = static_cast<NoActiveReason>(std::min<std::uint32_t>(e.a, 2));
    return fmt::format("NO MASTER IS ACTIVE: {}; the slaves get no process data", to_string(reason));
}

std::string_view refusal_text(std::uint32_t code) { return to_string(static_cast<HandOffRefusal>(code)); }

std::string hand_off(const Event& e, const EventDescriber&) {
    switch (static_cast<HandOffPhase>(e.a)) {
        case HandOffPhase::Announced:
            return fmt::format("switchover: hand-off to the partner announced for cycle {}", e.b);
        case HandOffPhase::Acknowledged:
            return fmt::format("switchover: the partner acknowledged, it takes over at cycle {}", e.b);
        case HandOffPhase::SteppedDown:
            return fmt::format("switchover: last cycle sent, now INACTIVE; the partner sends from cycle {}", e.b);
        case HandOffPhase::TakenOver:
            return fmt::format("switchover: took over at cycle {} as the partner announced (hot, no cycle lost)", e.b);
        case HandOffPhase::Cancelled:
            return fmt::format("switchover for cycle {} cancelled: {}", e.b, refusal_text(e.c));
        case HandOffPhase::Refused: return fmt::format("switchover refused: {}", refusal_text(e.c));
    }
    return "hand-off";
}

std::string partner_lost(const Event& e, const EventDescriber&) {
    return fmt::format("partner lost: its last answer in the CMF is {} ms old; still ACTIVE, no hot standby until it "
                       "answers again",
                       e.a);
}

std::string partner_found(const Event& e, const EventDescriber&) {
    return e.a == 0 ? std::string("partner found: it answers in the CMF")
                    : fmt::format("partner found again after {} ms without an answer", e.a);
}

}  // namespace

std::string_view to_string(HandOffRefusal refusal) {
    switch (refusal) {
        case HandOffRefusal::None: return "";
        case HandOffRefusal::PartnerNotAnswering: return "the partner does not answer in the CMF";
        case HandOffRefusal::PartnerCold: return "the partner is no hot standby (it does not mirror this master)";
        case HandOffRefusal::PartnerForced: return "the partner is forced to standby";
        case HandOffRefusal::PartnerDiffers: return "the partner runs another ENI or other pair parameters";
        case HandOffRefusal::PartnerLinkDown: return "one of the partner's links is down";
        case HandOffRefusal::NotAcknowledged: return "the partner did not acknowledge the hand-off in time";
        case HandOffRefusal::NotActive: return "this master is not ACTIVE";
        case HandOffRefusal::AlreadyRunning: return "a hand-off is already under way";
        case HandOffRefusal::PartnerLost: return "the partner went silent";
        case HandOffRefusal::ForcedStandby:
            return "this master was forced to standby (the ACTIVE keeps the bus unless it has stepped down already)";
    }
    return "unknown reason";
}

std::string_view to_string(NoActiveReason reason) {
    switch (reason) {
        case NoActiveReason::ForcedStandby: return "this member is forced to standby and no ACTIVE partner is heard";
        case NoActiveReason::PartnerDiffers:
            return "the only master heard runs another ENI or other pair parameters and has gone silent";
        case NoActiveReason::Isolated: return "both of this member's links are down";
    }
    return "?";
}

namespace events {

constinit const master::EventType kCommTimeout{"comm-timeout", comm_timeout};
constinit const master::EventType kAllLinksLost{"all-links-lost", all_links_lost};
constinit const master::EventType kLinksRestored{"links-restored", links_restored};
constinit const master::EventType kFramesNotReturning{"frames-not-returning", frames_not_returning};
constinit const master::EventType kFramesReturning{"frames-returning", frames_returning};
constinit const master::EventType kStandbyForced{"standby-forced", standby_forced};
constinit const master::EventType kNoActiveMaster{"no-active-master", no_active_master};
constinit const master::EventType kHandOff{"hand-off", hand_off};
constinit const master::EventType kPartnerLost{"partner-lost", partner_lost};
constinit const master::EventType kPartnerFound{"partner-found", partner_found};

}  // namespace events
}  // namespace ecpair::supervisor
