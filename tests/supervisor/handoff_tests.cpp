// The ACTIVE's side of a hand-off, and when one may not start.

#include <catch2/catch.hpp>

#include "ecpair/supervisor/handoff.hpp"

using namespace ecpair;
using namespace ecpair::supervisor;
using namespace std::chrono_literals;
using Step = HandOffAnnouncement::Step;

namespace {

redundancy::CmfStandbyStatus hot_partner() {
    redundancy::CmfStandbyStatus s;
    s.hot = true;
    s.main_link_up = true;
    s.red_link_up = true;
    return s;
}

}  // namespace

TEST_CASE("a hand-off steps down at its cycle once acknowledged", "[supervisor]") {
    HandOffAnnouncement handoff(104);
    auto partner = hot_partner();
    CHECK(handoff.step(100, partner) == Step::Announce);
    partner.handoff_acknowledged = true;
    partner.handoff_cycle_low = 104;
    CHECK(handoff.step(101, partner) == Step::Acknowledged);
    CHECK(handoff.committed());
    CHECK(handoff.step(102, partner) == Step::Announce);
    CHECK(handoff.step(103, partner) == Step::Announce);  // H-1: the last cycle, still announced
    CHECK(handoff.step(104, partner) == Step::StepDown);
}

TEST_CASE("an acknowledgement of another cycle does not commit", "[supervisor]") {
    HandOffAnnouncement handoff(104);
    auto partner = hot_partner();
    partner.handoff_acknowledged = true;
    partner.handoff_cycle_low = 99;
    CHECK(handoff.step(101, partner) == Step::Announce);
    CHECK(handoff.step(102, partner) == Step::Announce);
    CHECK(handoff.step(103, partner) == Step::Cancel);  // not committed by H-1
    CHECK_FALSE(handoff.committed());
}

TEST_CASE("a hand-off needs a partner that answers as a hot standby with both links", "[supervisor]") {
    using supervisor::HandOffRefusal;
    const auto partner = hot_partner();
    CHECK_FALSE(handoff_refusal(partner, 5ms, 100ms));
    CHECK(handoff_refusal(std::nullopt, std::nullopt, 100ms) == HandOffRefusal::PartnerNotAnswering);
    CHECK(handoff_refusal(partner, 150ms, 100ms) == HandOffRefusal::PartnerNotAnswering);
    auto cold = partner;
    cold.hot = false;
    CHECK(handoff_refusal(cold, 5ms, 100ms) == HandOffRefusal::PartnerCold);
    auto forced = partner;
    forced.forced = true;
    CHECK(handoff_refusal(forced, 5ms, 100ms) == HandOffRefusal::PartnerForced);
    auto differs = partner;
    differs.partner_differs = true;
    CHECK(handoff_refusal(differs, 5ms, 100ms) == HandOffRefusal::PartnerDiffers);
    auto link_down = partner;
    link_down.main_link_up = false;
    CHECK(handoff_refusal(link_down, 5ms, 100ms) == HandOffRefusal::PartnerLinkDown);
}
