#include "ecpair/supervisor/handoff.hpp"

namespace ecpair::supervisor {

std::optional<HandOffRefusal> handoff_refusal(const std::optional<redundancy::CmfStandbyStatus>& partner,
                                              std::optional<std::chrono::nanoseconds> answer_age,
                                              std::chrono::nanoseconds partner_silence) {
    if (!partner || !answer_age || *answer_age > partner_silence) return HandOffRefusal::PartnerNotAnswering;
    if (partner->partner_differs) return HandOffRefusal::PartnerDiffers;
    if (partner->forced) return HandOffRefusal::PartnerForced;
    if (!partner->hot) return HandOffRefusal::PartnerCold;
    if (!partner->main_link_up || !partner->red_link_up) return HandOffRefusal::PartnerLinkDown;
    return std::nullopt;
}

HandOffAnnouncement::Step HandOffAnnouncement::step(std::uint64_t cycle,
                                                    const std::optional<redundancy::CmfStandbyStatus>& partner) {
    if (!committed_ && partner && partner->handoff_acknowledged &&
        partner->handoff_cycle_low == static_cast<std::uint32_t>(cycle_)) {
        committed_ = true;
        if (cycle < cycle_) return Step::Acknowledged;
    }
    if (cycle >= cycle_) return committed_ ? Step::StepDown : Step::Cancel;
    if (!committed_ && cycle + 1 >= cycle_) return Step::Cancel;  // H-1: the last CMF that could announce it
    return Step::Announce;
}

}  // namespace ecpair::supervisor
