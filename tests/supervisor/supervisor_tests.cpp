// Every decision path of the Supervisor, cycle by cycle in virtual time (no
// sleeps): start-up, the communication timeout and what may stop a takeover,
// link loss, isolation, partner lost / found, frames not returning,
// collisions, the hand-off on both sides, force standby, operator requests.

#include <catch2/catch.hpp>

#include <memory>

#include "supervisor_harness.hpp"

using namespace ecpair;
using namespace std::chrono_literals;
using ecpair::master::EventKind;
using ecpair::supervisor::SupervisorState;
using ecpair::test::SupervisorHarness;
using RedState = ecpair::redundancy::RedState;

namespace {

// A member that heard its partner at start-up and stands by, mirroring it.
std::unique_ptr<SupervisorHarness> standing_by(
    supervisor::SupervisorOptions options = SupervisorHarness::default_options()) {
    auto owner = std::make_unique<SupervisorHarness>(options);
    auto& h = *owner;
    h.cycle();  // starts listening
    h.partner_cmf();
    h.cycle();
    REQUIRE(h.state() == SupervisorState::Standby);
    return owner;
}

// A member that took the bus at start-up and has a hot standby partner.
std::unique_ptr<SupervisorHarness> active_with_partner() {
    auto options = SupervisorHarness::default_options();
    options.start_active = true;
    auto owner = std::make_unique<SupervisorHarness>(options);
    auto& h = *owner;
    h.partner_answer();
    h.cycle();
    REQUIRE(h.active());
    REQUIRE(h.state() == SupervisorState::Active);
    return owner;
}

}  // namespace

// ---- start-up

TEST_CASE("a member that hears no ACTIVE while listening takes the bus", "[supervisor]") {
    SupervisorHarness h;
    h.cycle();
    CHECK(h.state() == SupervisorState::Listening);
    CHECK_FALSE(h.active());
    const int took = h.until([&] { return h.active(); });
    CHECK(took >= 200);  // listen_time 200 ms + jitter (half of 10 ms)
    CHECK(took <= 206);
    CHECK(h.state() == SupervisorState::Active);
    CHECK(h.last.epoch == 1);
    REQUIRE(h.find(arbitration::events::kArbitrationSettled));
    CHECK(h.find(arbitration::events::kArbitrationSettled)->a ==
          static_cast<std::uint32_t>(arbitration::ArbitrationOutcome::TookBusAfterListening));
}

TEST_CASE("a member that hears an ACTIVE while listening stands by and never preempts it", "[supervisor]") {
    SupervisorHarness h;
    h.cycle();
    h.cycles(30);
    for (int i = 0; i < 2000; ++i) {
        h.partner_cmf(true, 7);
        h.cycle();
        REQUIRE_FALSE(h.active());
    }
    CHECK(h.state() == SupervisorState::Standby);
    CHECK(h.supervisor.status().epoch == 7);  // the newest epoch heard
    CHECK(h.last.ready_for_handoff);          // a hot standby
}

TEST_CASE("the longest silence in the status is what a standby counted, not the listening at start",
          "[supervisor]") {
    SupervisorHarness h;
    h.cycle();
    h.cycles(150);  // listening: 150 ms without an ACTIVE heard
    for (int i = 0; i < 100; ++i) {
        h.partner_cmf();
        h.cycle();
        if (i == 40) h.cycles(20);  // the ACTIVE silent for 20 cycles, then heard again
    }
    REQUIRE(h.state() == SupervisorState::Standby);
    CHECK(h.supervisor.status().longest_silence == 21ms);  // CMFs 21 cycles apart
}

TEST_CASE("a member started in forced standby never takes the bus until released", "[supervisor]") {
    auto options = SupervisorHarness::default_options();
    options.start_in_forced_standby = true;
    SupervisorHarness h(options);
    h.cycles(1000);
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::NoActive);
    CHECK(h.supervisor.status().no_active == supervisor::NoActiveReason::ForcedStandby);
    CHECK(h.last.forced_standby);
    CHECK(h.raised(supervisor::events::kStandbyForced));

    h.supervisor.force_standby(false);
    h.cycle();
    CHECK(h.state() == SupervisorState::Listening);
    CHECK(h.until([&] { return h.active(); }) > 0);
}

// ---- the communication timeout

TEST_CASE("a standby whose ACTIVE falls silent takes over hot after the comm timeout", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    for (int i = 0; i < 100; ++i) {
        h.partner_cmf();
        h.cycle();
    }
    const int took = h.until([&] { return h.active(); });
    CHECK(took >= 50);
    CHECK(took <= 51);
    CHECK(h.state() == SupervisorState::Active);
    const auto* timeout = h.find(supervisor::events::kCommTimeout);
    REQUIRE(timeout);
    CHECK(timeout->a >= 50);
    CHECK(timeout->b == 50);
    CHECK(timeout->c == static_cast<std::uint32_t>(supervisor::SilenceAction::TakingOverHot));
    CHECK(timeout->d == 0);
    CHECK(h.supervisor.status().counters.comm_timeouts == 1);
}

TEST_CASE("without a fresh mirror the takeover after a comm timeout is cold", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.seen.mirror_fresh = false;
    h.until([&] { return h.active(); });
    const auto* timeout = h.find(supervisor::events::kCommTimeout);
    REQUIRE(timeout);
    CHECK(timeout->c == static_cast<std::uint32_t>(supervisor::SilenceAction::TakingOverCold));
}

TEST_CASE("a stall of this machine does not count as the partner's silence", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    // 200 ms in which this member itself did not run (a VM pause): it counts as two cycles.
    h.cycle(200ms);
    CHECK_FALSE(h.active());
    CHECK(h.supervisor.status().silence <= 3ms);
    h.partner_cmf();  // the partner resumes too
    h.cycle();
    h.cycles(30);
    CHECK_FALSE(h.active());
}

TEST_CASE("a link of ours going down shortens the wait when no CMF arrives on the other", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.seen.main_link_up = false;  // the dead partner's link guard took its links down
    const int took = h.until([&] { return h.active(); });
    CHECK(took >= 3);
    CHECK(took <= 4);
    const auto* timeout = h.find(supervisor::events::kCommTimeout);
    REQUIRE(timeout);
    CHECK(timeout->d == 1);
}

TEST_CASE("our own link guard takes MAIN and RED down: isolated within the confirm window, no takeover",
          "[supervisor]") {
    // The guard takes both links down when this member's cycle hung; the
    // daemon reports the two losses a cycle apart at worst. The shortened wait
    // must not call the partner failed before the second loss is seen.
    auto owner = standing_by();
    auto& h = *owner;
    h.seen.main_link_up = false;
    h.cycle();
    h.seen.red_link_up = false;
    h.cycles(500);
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Isolated);
    CHECK_FALSE(h.raised(redundancy::events::kTakeover));
}

TEST_CASE("a pulled master-master cable takes a link down but the CMF still arrives: no takeover",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.seen.main_link_up = false;
    for (int i = 0; i < 500; ++i) {
        h.partner_cmf();  // through the slaves, on RED
        h.cycle();
        REQUIRE_FALSE(h.active());
    }
    CHECK_FALSE(h.raised(supervisor::events::kCommTimeout));
}

TEST_CASE("a forced standby reports its silent partner but does not take over", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.supervisor.force_standby(true);
    h.cycles(200);
    CHECK_FALSE(h.active());
    const auto* timeout = h.find(supervisor::events::kCommTimeout);
    REQUIRE(timeout);
    CHECK(timeout->c == static_cast<std::uint32_t>(supervisor::SilenceAction::RefusedForced));
    CHECK(h.state() == SupervisorState::NoActive);
    CHECK(h.raised(supervisor::events::kNoActiveMaster));
}

TEST_CASE("a partner that runs another ENI is not taken over from, unless configured", "[supervisor]") {
    SECTION("default: no takeover") {
        SupervisorHarness h;
        h.cycle();
        h.partner_cmf(false);
        h.cycle();
        REQUIRE(h.state() == SupervisorState::Standby);
        h.cycles(300);
        CHECK_FALSE(h.active());
        REQUIRE(h.find(supervisor::events::kCommTimeout));
        CHECK(h.find(supervisor::events::kCommTimeout)->c ==
              static_cast<std::uint32_t>(supervisor::SilenceAction::RefusedPartnerDiffers));
        CHECK(h.supervisor.status().no_active == supervisor::NoActiveReason::PartnerDiffers);
    }
    SECTION("takeover_from_differing_partner") {
        auto options = SupervisorHarness::default_options();
        options.takeover_from_differing_partner = true;
        SupervisorHarness h(options);
        h.cycle();
        h.partner_cmf(false);
        h.cycle();
        h.seen.mirror_fresh = false;
        CHECK(h.until([&] { return h.active(); }, 300) > 0);
    }
}

// ---- links

TEST_CASE("an INACTIVE with both links down is isolated and never takes over", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.seen.main_link_up = false;
    h.seen.red_link_up = false;
    h.cycles(500);
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Isolated);
    CHECK(h.supervisor.status().no_active == supervisor::NoActiveReason::Isolated);
    REQUIRE(h.find(supervisor::events::kAllLinksLost));
    CHECK(h.find(supervisor::events::kAllLinksLost)->a == 0);

    h.seen.red_link_up = true;  // a link back: listen again
    h.cycle();
    CHECK(h.raised(supervisor::events::kLinksRestored));
    CHECK(h.state() == SupervisorState::Listening);
}

TEST_CASE("an ACTIVE that loses both links becomes INACTIVE", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    h.seen.main_link_up = false;
    h.seen.red_link_up = false;
    h.cycle();
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Isolated);
    REQUIRE(h.find(supervisor::events::kAllLinksLost));
    CHECK(h.find(supervisor::events::kAllLinksLost)->a == 1);
}

// ---- the ACTIVE watches its partner and its frames

TEST_CASE("the ACTIVE reports its partner lost with the age of the last answer, and found again",
          "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    CHECK(h.raised(supervisor::events::kPartnerFound));
    h.cycles(150);
    const auto* lost = h.find(supervisor::events::kPartnerLost);
    REQUIRE(lost);
    CHECK(lost->a >= 100);
    CHECK(lost->a <= 102);
    CHECK(h.active());  // still ACTIVE

    h.got.clear();
    h.partner_answer();
    h.cycle();
    const auto* found = h.find(supervisor::events::kPartnerFound);
    REQUIRE(found);
    CHECK(found->a >= 100);  // silent for about 150 ms
}

TEST_CASE("frames that do not come back are reported once, and their return too", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    h.seen.cycles_without_return = 19;
    h.cycle();
    CHECK_FALSE(h.raised(supervisor::events::kFramesNotReturning));
    h.seen.cycles_without_return = 20;
    h.cycle();
    h.seen.cycles_without_return = 21;
    h.cycle();
    CHECK(std::count_if(h.got.begin(), h.got.end(),
                        [](const auto& e) { return e.kind == supervisor::events::kFramesNotReturning; }) == 1);
    CHECK(h.active());  // keeps trying
    h.seen.cycles_without_return = 0;
    h.cycle();
    CHECK(h.raised(supervisor::events::kFramesReturning));
}

TEST_CASE("after a takeover from a silent partner, frames not returning name its links as the likely cause",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.until([&] { return h.active(); });
    h.seen.cycles_without_return = 20;
    h.cycle();
    const auto* e = h.find(supervisor::events::kFramesNotReturning);
    REQUIRE(e);
    CHECK(e->b == 1);
    CHECK_THAT(master::EventDescriber(nullptr, nullptr).describe(*e),
               Catch::Contains("failed partner's links are still up"));
}

// ---- collisions

TEST_CASE("another master's frames in three cycles running are a collision: stop, back off, retake in silence",
          "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    h.foreign_frames();
    h.cycle();
    h.foreign_frames();
    h.cycle();
    CHECK(h.active());  // two cycles: a straggler, not yet a collision
    h.foreign_frames();
    h.cycle();
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::BackingOff);
    const auto* collision = h.find(arbitration::events::kCollision);
    REQUIRE(collision);
    CHECK(collision->a == 1);
    // settle 5 cycles + a random draw in 1..10 ms (0.5 -> 5.5 ms).
    CHECK(collision->b == 10500);
    const int took = h.until([&] { return h.active(); });
    CHECK(took >= 10);
    CHECK(took <= 11);
    CHECK(h.last.epoch == 2);
    CHECK(h.supervisor.status().counters.backoffs_won == 1);
}

TEST_CASE("a master heard while backing off took the bus back: yield and stand by", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    for (int i = 0; i < 3; ++i) {
        h.foreign_frames();
        h.cycle();
    }
    REQUIRE(h.state() == SupervisorState::BackingOff);
    h.cycles(6);  // past the settle time
    h.partner_cmf(true, 2);
    h.cycle();
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Standby);
    CHECK(h.supervisor.status().counters.backoffs_lost == 1);
}

TEST_CASE("after a double line break the half that reaches fewer slaves defers to the bigger one",
          "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    h.seen.slaves_reached = 2;  // our half
    h.partner_reach = 3;        // the other ACTIVE's half
    for (int i = 0; i < 3; ++i) {
        h.partner_cmf(true, 2);  // its CMF arrives among its foreign frames
        h.foreign_frames();
        h.cycle();
    }
    const auto* collision = h.find(arbitration::events::kCollision);
    REQUIRE(collision);
    CHECK(collision->c == static_cast<std::uint32_t>(arbitration::BackoffKind::Deferring));
    CHECK(collision->d == static_cast<std::uint32_t>(arbitration::DecidedBy::SlavesReached));
    CHECK_THAT(master::EventDescriber(nullptr, nullptr).describe(*collision), Catch::Contains("reaches more slaves"));
}

// ---- switchover, ACTIVE side

TEST_CASE("a switchover hands the bus over at the announced cycle once the partner acknowledges",
          "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    REQUIRE(h.supervisor.switchover());
    h.partner_answer();
    h.cycle();
    REQUIRE(h.last.handoff_cycle);
    const auto at = *h.last.handoff_cycle;
    CHECK(at == h.seen.cycle + 8);
    CHECK(h.state() == SupervisorState::HandingOver);
    h.partner_answer(true, false, true);  // acknowledged in the returned CMF
    h.cycle();
    CHECK(h.active());
    while (h.seen.cycle + 1 < at) {
        h.partner_answer(true, false, true);
        h.cycle();
        CHECK(h.active());
        CHECK(h.last.handoff_cycle == at);  // still announced in the last cycle, H-1
    }
    h.partner_answer(true, false, true);
    h.cycle();  // cycle H
    CHECK(h.seen.cycle == at);
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Standby);
    CHECK(h.supervisor.status().counters.handoffs == 1);
}

TEST_CASE("a switchover the partner does not acknowledge is withdrawn in the last cycle", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    REQUIRE(h.supervisor.switchover());
    h.partner_answer();
    h.cycle();
    const auto at = *h.last.handoff_cycle;
    while (h.seen.cycle + 1 < at) {
        h.partner_answer();
        h.cycle();
    }
    CHECK_FALSE(h.last.handoff_cycle);  // withdrawn in H-1's CMF
    CHECK(h.active());
    CHECK(h.state() == SupervisorState::Active);
    REQUIRE(h.find(supervisor::events::kHandOff));
    CHECK(h.got.back().kind == supervisor::events::kHandOff);
    CHECK(h.got.back().a == static_cast<std::uint32_t>(supervisor::HandOffPhase::Cancelled));
    h.cycles(10);
    CHECK(h.active());
}

TEST_CASE("the CMF says a switchover is committed from the acknowledgement on, and a committed one is never "
          "withdrawn: a stall of ours past the partner silence still ends in the step-down at H",
          "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    REQUIRE(h.supervisor.switchover());
    h.partner_answer();
    h.cycle();
    const auto at = *h.last.handoff_cycle;
    CHECK_FALSE(h.last.handoff_committed);  // announced, not yet acknowledged
    h.partner_answer(true, false, true);
    h.cycle();
    CHECK(h.last.handoff_committed);
    // This machine stalls 150 ms (more than partner_silence) before H: without
    // the commitment this would cancel with "partner lost" and keep the bus,
    // while the partner, which read "committed", takes it at H.
    h.cycle(150ms);
    while (h.seen.cycle < at) h.cycle();
    CHECK(h.seen.cycle == at);
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Standby);
    CHECK(h.supervisor.status().counters.handoffs == 1);
    CHECK(h.supervisor.status().counters.handoffs_cancelled == 0);
}

TEST_CASE("a switchover onto a partner that is no hot standby is refused with the reason", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    SECTION("cold") {
        h.partner_answer(false);
        h.cycle();
        const auto refused = h.supervisor.switchover();
        REQUIRE_FALSE(refused);
        CHECK(refused.error().find("no hot standby") != std::string::npos);
    }
    SECTION("forced") {
        h.partner_answer(true, true);
        h.cycle();
        const auto refused = h.supervisor.switchover();
        REQUIRE_FALSE(refused);
        CHECK(refused.error().find("forced to standby") != std::string::npos);
    }
    SECTION("silent") {
        h.cycles(150);
        const auto refused = h.supervisor.switchover();
        REQUIRE_FALSE(refused);
        CHECK(refused.error().find("does not answer") != std::string::npos);
    }
    SECTION("a link of the partner down") {
        h.partner_answer();
        h.seen.partner_status->red_link_up = false;
        h.cycle();
        const auto refused = h.supervisor.switchover();
        REQUIRE_FALSE(refused);
        CHECK(refused.error().find("link") != std::string::npos);
    }
    CHECK(h.active());
}

TEST_CASE("the partner asking for a switchover in its standby status starts one", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    h.partner_answer();
    h.seen.partner_status->switchover_requested = true;
    h.cycle();
    CHECK(h.state() == SupervisorState::HandingOver);
}

TEST_CASE("forcing the ACTIVE to standby hands over to a hot partner, else steps down", "[supervisor]") {
    auto owner = active_with_partner();
    auto& h = *owner;
    SECTION("hot partner: a hand-off") {
        h.supervisor.force_standby(true);
        h.partner_answer();
        h.cycle();
        CHECK(h.state() == SupervisorState::HandingOver);
    }
    SECTION("partner forced too: step down, nobody is ACTIVE, and the status says so") {
        h.partner_answer(true, true);
        h.cycle();
        h.supervisor.force_standby(true);
        h.partner_answer(true, true);
        h.cycle();
        CHECK_FALSE(h.active());
        CHECK(h.state() == SupervisorState::NoActive);
        CHECK(h.supervisor.status().no_active == supervisor::NoActiveReason::ForcedStandby);
        h.cycles(500);
        CHECK_FALSE(h.active());
    }
}

// ---- switchover, INACTIVE side

TEST_CASE("a standby acknowledges an announced hand-off and takes over at its cycle", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.partner_cmf();
    h.cycle();
    CHECK(h.last.ready_for_handoff);
    const std::uint64_t at = h.seen.cycle + 4;
    h.announced_handoff = at;
    h.partner_cmf();  // announces; the controller acknowledges
    h.cycle();
    CHECK(h.state() == SupervisorState::HandOffPending);
    h.announced_committed = true;  // the ACTIVE read the acknowledgement
    while (!h.active() && h.seen.cycle < at + 5) {
        h.partner_cmf();
        h.cycle();
    }
    CHECK(h.active());
    CHECK(h.seen.cycle == at);  // at the boundary of cycle H, where H-1 was mirrored
    REQUIRE(h.find(supervisor::events::kHandOff));
    CHECK(h.got.back().kind == supervisor::events::kHandOff);
    CHECK(h.got.back().a == static_cast<std::uint32_t>(supervisor::HandOffPhase::TakenOver));
    CHECK(h.supervisor.status().counters.handoffs == 1);
}

TEST_CASE("a standby whose ACTIVE withdraws the hand-off stays INACTIVE", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.announced_handoff = h.seen.cycle + 4;
    h.partner_cmf();
    h.cycle();
    REQUIRE(h.state() == SupervisorState::HandOffPending);
    h.announced_handoff.reset();
    h.partner_cmf();
    h.cycle();
    CHECK(h.state() == SupervisorState::Standby);
    h.cycles(3);
    for (int i = 0; i < 20; ++i) {
        h.partner_cmf();
        h.cycle();
    }
    CHECK_FALSE(h.active());
}

TEST_CASE("a standby takes over at H when the ACTIVE's last CMF (H-1) is lost, once a CMF said committed",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    const std::uint64_t at = h.seen.cycle + 4;
    h.announced_handoff = at;
    h.partner_cmf();  // cycle H-4: announced, acknowledged
    h.cycle();
    REQUIRE(h.state() == SupervisorState::HandOffPending);
    h.announced_committed = true;
    h.partner_cmf();  // H-3: committed
    h.cycle();
    h.partner_cmf();  // H-2
    h.cycle();
    CHECK(h.seen.cycle == at - 1);
    h.cycle();  // H-1's CMF never arrives
    CHECK(h.seen.cycle == at);
    CHECK(h.active());  // at H itself: the slaves miss no cycle
    const auto* taken = h.find(supervisor::events::kHandOff);
    REQUIRE(taken);
    CHECK(taken->a == static_cast<std::uint32_t>(supervisor::HandOffPhase::TakenOver));
    CHECK(taken->b == static_cast<std::uint32_t>(at));
}

TEST_CASE("a standby that reads \"committed\" only after its boundary H takes over then and still sends cycle H "
          "first: no cycle number is skipped",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    const std::uint64_t at = h.seen.cycle + 4;
    h.announced_handoff = at;
    for (int i = 0; i < 3; ++i) {  // H-4 .. H-2: announced, not yet committed
        h.partner_cmf();
        h.cycle();
    }
    h.cycle();  // H-1's CMF, the one saying committed, is late
    CHECK(h.seen.cycle == at);
    CHECK_FALSE(h.active());
    h.announced_committed = true;
    h.partner_cmf();  // it arrives within our cycle H
    h.cycle();
    CHECK(h.seen.cycle == at + 1);
    CHECK(h.active());
    REQUIRE(h.last.first_cycle);
    CHECK(*h.last.first_cycle == at);
    h.cycle();
    CHECK_FALSE(h.last.first_cycle);  // only the first cycle as ACTIVE is renumbered
}

TEST_CASE("a standby does not take a committed hand-off while the ACTIVE is late (a stall): it waits for the "
          "ACTIVE's cycles up to H-2",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    const std::uint64_t at = h.seen.cycle + 6;
    h.announced_handoff = at;
    h.announced_committed = true;
    h.partner_cmf();  // H-6: announced, committed
    h.cycle();
    REQUIRE(h.state() == SupervisorState::HandOffPending);
    const auto last_cmf = h.seen.cycle - 1;  // H-6
    // The ACTIVE's machine stalls: nothing for 8 cycles, our count runs past H.
    for (int i = 0; i < 8; ++i) {
        h.cycle();
        CHECK_FALSE(h.active());
    }
    CHECK(h.seen.cycle > at);
    // It resumes and sends H-5 .. H-2 late, one per our cycle: we count with it again.
    for (auto c = last_cmf + 1; c + 2 <= at; ++c) {
        CHECK_FALSE(h.active());
        h.partner_cmf();
        h.seen.heard->cycle = c;
        h.seen.mirrored_cycle = c;
        h.seen.cycle = c;  // the controller's count follows the mirrored cycle
        h.cycle();
    }
    CHECK(h.seen.cycle == at - 1);
    CHECK_FALSE(h.active());
    h.cycle();  // H: H-2 mirrored, H-1 missing
    CHECK(h.seen.cycle == at);
    CHECK(h.active());
}

TEST_CASE("a standby that never heard the hand-off committed does not take the bus on silence at H: the ACTIVE may "
          "have withdrawn it in the CMFs that were lost (the comm timeout decides)",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    const std::uint64_t at = h.seen.cycle + 4;
    h.announced_handoff = at;
    for (int i = 0; i < 3; ++i) {  // H-4 .. H-2: announced, never committed
        h.partner_cmf();
        h.cycle();
    }
    REQUIRE(h.state() == SupervisorState::HandOffPending);
    // H-1 (which withdrew it) and everything after is lost: the ACTIVE may
    // still hold the bus. Two masters would number the same cycles.
    for (int i = 0; i < 40; ++i) {
        h.cycle();
        CHECK_FALSE(h.active());
    }
    const int took = h.until([&] { return h.active(); });
    CHECK(took > 0);
    CHECK(took <= 12);  // the comm timeout (50 ms) from the last CMF at H-2
    const auto* timeout = h.find(supervisor::events::kCommTimeout);
    REQUIRE(timeout);
    CHECK(timeout->c == static_cast<std::uint32_t>(supervisor::SilenceAction::TakingOverHot));
    CHECK(h.supervisor.status().counters.handoffs == 0);
}

TEST_CASE("an older CMF without the announcement that arrives late does not cancel a committed hand-off",
          "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    const std::uint64_t at = h.seen.cycle + 4;
    h.announced_handoff = at;
    h.announced_committed = true;
    h.partner_cmf();
    h.cycle();
    REQUIRE(h.state() == SupervisorState::HandOffPending);
    h.announced_handoff.reset();  // a CMF from before the announcement, arriving last
    h.partner_cmf();
    h.seen.heard->cycle = at - 6;
    h.cycle();
    CHECK(h.state() == SupervisorState::HandOffPending);
    h.announced_handoff = at;
    while (h.seen.cycle < at) {
        h.partner_cmf();
        h.cycle();
    }
    CHECK(h.active());
    CHECK(h.supervisor.status().counters.handoffs_cancelled == 0);
}

namespace {

// A standby that took a committed hand-off at `at` from its partner, whose
// last CMF (H-1) has not arrived: the partner ran late.
std::unique_ptr<SupervisorHarness> took_handoff(std::uint64_t& at) {
    auto owner = standing_by();
    auto& h = *owner;
    at = h.seen.cycle + 4;
    h.announced_handoff = at;
    h.announced_committed = true;
    while (h.seen.cycle + 1 < at) {  // the CMFs of H-4 .. H-2
        h.partner_cmf();
        h.cycle();
    }
    h.cycle();  // our boundary H
    REQUIRE(h.active());
    REQUIRE(h.seen.cycle == at);
    return owner;
}

}  // namespace

TEST_CASE("after a hand-off, the late last cycles of the master that handed over are no collision", "[supervisor]") {
    std::uint64_t at = 0;
    auto owner = took_handoff(at);
    auto& h = *owner;
    // Its H-1 arrives over our next cycles (our cycle thread catching up
    // spreads one cycle's frames over several of ours), its CMF among them.
    for (int i = 0; i < 4; ++i) {
        h.foreign_frames(true);
        if (i == 1) {
            h.partner_cmf();
            h.seen.heard->cycle = at - 1;
        }
        h.cycle();
        CHECK(h.active());
    }
    CHECK_FALSE(h.raised(arbitration::events::kCollision));
    CHECK(h.supervisor.status().counters.collisions == 0);
}

TEST_CASE("after a hand-off, a CMF of the master that handed over numbering H or later is a collision",
          "[supervisor]") {
    std::uint64_t at = 0;
    auto owner = took_handoff(at);
    auto& h = *owner;
    h.foreign_frames(true);
    h.partner_cmf();
    h.seen.heard->cycle = at + 1;  // it did not stop at H
    h.cycle();
    h.foreign_frames(true);
    h.cycle();
    CHECK(h.active());
    h.foreign_frames(true);
    h.cycle();
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::BackingOff);
    CHECK(h.raised(arbitration::events::kCollision));
}

TEST_CASE("after a hand-off, another master's frames are a collision as ever", "[supervisor]") {
    std::uint64_t at = 0;
    auto owner = took_handoff(at);
    auto& h = *owner;
    for (int i = 0; i < 3; ++i) {
        h.foreign_frames(false);
        if (i == 1) h.foreign_frames(true);  // the master that handed over's with them: the cycle still counts
        h.cycle();
    }
    CHECK(h.state() == SupervisorState::BackingOff);
}

TEST_CASE("the master that handed over is excused only until it answers as our standby, and the settle time more",
          "[supervisor]") {
    std::uint64_t at = 0;
    SECTION("it answers") {
        auto owner = took_handoff(at);
        auto& h = *owner;
        h.partner_answer();
        h.cycle();
        h.cycles(5);  // the settle time: collision_cycles + 2 = 5 cycles
        CHECK(h.active());
        h.foreign_frames(true);
        h.cycle();  // 6 ms after its answer: its frames count again
        h.foreign_frames(true);
        h.cycle();
        h.foreign_frames(true);
        h.cycle();
        CHECK(h.state() == SupervisorState::BackingOff);
    }
    SECTION("it never answers: comm_timeout after H at most") {
        auto owner = took_handoff(at);
        auto& h = *owner;
        for (int i = 0; i < 50; ++i) {
            h.foreign_frames(true);
            h.cycle();
            REQUIRE(h.active());
        }
        h.foreign_frames(true);
        h.cycle();
        h.foreign_frames(true);
        h.cycle();
        h.foreign_frames(true);
        h.cycle();
        CHECK(h.state() == SupervisorState::BackingOff);
    }
}

TEST_CASE("a forced standby does not acknowledge a hand-off", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.supervisor.force_standby(true);
    h.partner_cmf();
    h.cycle();
    CHECK_FALSE(h.last.ready_for_handoff);
    CHECK(h.last.forced_standby);
    const auto refused = h.supervisor.switchover();
    REQUIRE_FALSE(refused);
}

TEST_CASE("a switchover asked at the standby is passed to the ACTIVE in the standby status", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.partner_cmf();
    h.cycle();
    REQUIRE(h.supervisor.switchover());
    h.partner_cmf();
    h.cycle();
    CHECK(h.last.switchover_requested);
}

// ---- operator override

TEST_CASE("the operator can make a standby ACTIVE and an ACTIVE step down", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    h.supervisor.request_role(RedState::Active);
    h.partner_cmf();
    h.cycle();
    CHECK(h.active());
    h.supervisor.request_role(RedState::Inactive);
    h.cycle();
    CHECK_FALSE(h.active());
    CHECK(h.state() == SupervisorState::Standby);
}

TEST_CASE("a standby forced after it acknowledged a hand-off does not take the bus", "[supervisor]") {
    auto owner = standing_by();
    auto& h = *owner;
    SECTION("forced before the acknowledgement is acted on") {
        h.announced_handoff = h.seen.cycle + 10;
        h.partner_cmf();  // acknowledged: the supervisor was ready
        REQUIRE(h.seen.acknowledged_handoff == h.announced_handoff);
        h.supervisor.force_standby(true);
    }
    SECTION("forced while the hand-off is pending") {
        h.announced_handoff = h.seen.cycle + 10;
        h.partner_cmf();
        h.cycle();
        REQUIRE(h.state() == SupervisorState::HandOffPending);
        h.supervisor.force_standby(true);
        h.partner_cmf();
        h.cycle();
        // The operator reads why the announced switchover did not happen.
        const auto* cancelled = h.find(supervisor::events::kHandOff);
        REQUIRE(cancelled);
        CHECK(cancelled->a == static_cast<std::uint32_t>(supervisor::HandOffPhase::Cancelled));
        CHECK(cancelled->b == static_cast<std::uint32_t>(*h.announced_handoff));
        CHECK(cancelled->c == static_cast<std::uint32_t>(supervisor::HandOffRefusal::ForcedStandby));
    }
    for (int i = 0; i < 30; ++i) {  // past the announced cycle, the stale acknowledgement still seen
        h.partner_cmf();
        h.cycle();
        CHECK_FALSE(h.active());
        CHECK(h.state() != SupervisorState::HandOffPending);
        CHECK_FALSE(h.last.ready_for_handoff);
    }
}
