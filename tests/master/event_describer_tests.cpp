// Operator texts of master events (issue 11, item 6): the frame by its
// number, state and datagrams, the acyclic request, the slave by name,
// position and station, what the master did, and the real cycle.

#include <string>

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/frame_tracker.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/wire/datagram.hpp"

using namespace ecpair;
using namespace ecpair::master;
using Catch::Contains;

namespace {

// EK1100 (1001), EL2008 (1002, outputs at 0x01000000), EL1008 (1003, inputs at 0x01000800);
// one cyclic frame: BRD AL status (Cnt 3), LWR 0x01000000 (Cnt 1), LRD 0x01000800 (Cnt 1).
std::shared_ptr<const eni::EniConfig> load_digital_io() {
    auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_extra/digital_io_device_emulation_3slaves.xml"));
    REQUIRE(loaded);
    return *loaded;
}

CyclicPlan plan_of(const eni::EniConfig& eni) {
    auto built = CyclicPlan::build(eni, PlanOptions{});
    REQUIRE(built);
    return *built;
}

struct Fixture {
    std::shared_ptr<const eni::EniConfig> eni = load_digital_io();
    CyclicPlan plan = plan_of(*eni);
    EventDescriber describer{eni, &plan};
};

Event event(EventKind kind, std::uint64_t cycle, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0,
            std::uint32_t d = 0) {
    return Event{kind, cycle, std::chrono::system_clock::now(), a, b, c, d};
}

}  // namespace

TEST_CASE("a lost cyclic frame is named by its number, state and datagrams, with the copies that came back") {
    Fixture f;
    Event e = event(events::kFrameLost, 4711, static_cast<std::uint32_t>(FrameKind::Cyclic), 0);
    LostFrameDetail detail;
    detail.master_state = static_cast<std::uint8_t>(eni::SlaveState::Op);
    detail.sent_main = detail.sent_red = true;
    detail.red_returned = true;
    detail.encode_into(e);
    CHECK(f.describer.describe(e) ==
          "cycle 4711: cyclic frame 1 of 1 (OP: BRD 0x0130, LWR 0x01000000 1 B, LRD 0x01000800 1 B) lost (MAIN copy "
          "missing, RED copy came back): this cycle's inputs keep their last values");
    // In PREOP the frame carries the AL status only.
    detail.master_state = static_cast<std::uint8_t>(eni::SlaveState::Preop);
    detail.encode_into(e);
    CHECK_THAT(f.describer.describe(e), Contains("(PREOP: BRD 0x0130)"));
}

TEST_CASE("a lost acyclic frame names its request and the slave it addressed") {
    Fixture f;
    Event e = event(events::kFrameLost, 12, static_cast<std::uint32_t>(FrameKind::Acyclic), 3);
    LostFrameDetail detail;
    detail.first_command = wire::Command::Fprd;
    detail.first_address = wire::DatagramHeader::physical(1002, 0x0130);
    detail.first_length = 6;
    detail.datagrams = 2;
    detail.sent_main = true;
    detail.encode_into(e);
    CHECK(f.describer.describe(e) ==
          "cycle 12: acyclic frame lost: FPRD to 'Term 2 (EL2008)' (position 2, station 1002), register 0x0130, 6 "
          "bytes and 1 more datagram(s) (MAIN copy missing, RED copy not sent): its requests are sent again until their "
          "timeout");
    detail.first_command = wire::Command::Aprd;
    detail.first_address = wire::DatagramHeader::physical(0xFFFE, 0x0012);  // the third slave
    detail.datagrams = 1;
    detail.encode_into(e);
    CHECK_THAT(f.describer.describe(e), Contains("APRD to 'Term 3 (EL1008)' (position 3, station 1003), register 0x0012"));
}

TEST_CASE("a cyclic WKC error names the datagram, its ENI line and the slaves that map it") {
    Fixture f;
    const auto text = f.describer.describe(event(events::kCyclicWkcError, 99, 0, 2, 1, 0));
    CHECK_THAT(text, Contains("cycle 99: cyclic frame 1 datagram 3 (LRD 0x01000800, 1 bytes, 'inputs', ENI line "));
    CHECK_THAT(text, Contains("came back with WKC 0, expected 1; the slaves mapping it: 'Term 3 (EL1008)' (position 3, "
                              "station 1003): the cycle's inputs are marked invalid"));
    CHECK_THAT(f.describer.describe(event(events::kCyclicWkcError, 99, 0, 0, 3, 2)),
               Contains("BRD 0x0130, 2 bytes, 'AL status'") && Contains("1 of the 3 slaves did not answer"));
}

TEST_CASE("slave events name the slave, line breaks name both ends") {
    Fixture f;
    CHECK(f.describer.describe(event(events::kSlaveStateError, 5, 1, 0x14, 0x001B)) ==
          "cycle 5: slave 'Term 2 (EL2008)' (position 2, station 1002) is in SAFEOP+ERR, AL status code 0x001b (sync "
          "manager watchdog)");
    CHECK(f.describer.describe(event(events::kSlavePresence, 6, 2, 0)) ==
          "cycle 6: slave 'Term 3 (EL1008)' (position 3, station 1003) is absent (no answer at its station address)");
    CHECK(f.describer.describe(event(events::kTransitionFailed, 7, 2, 4, 1)) ==
          "cycle 7: transition PREOP -> SAFEOP failed at slave 'Term 2 (EL2008)' (position 2, station 1002): the master "
          "stays in PREOP");
    CHECK(f.describer.describe(event(events::kLineBreak, 8, 1, 1)) ==
          "cycle 8: line break after slave 1 'Term 1 (EK1100)' (position 1, station 1001), before 'Term 2 (EL2008)' "
          "(position 2, station 1002): slaves 1-1 are reached from MAIN, 2-3 from RED; every slave stays in the cycle");
    CHECK_THAT(f.describer.describe(event(events::kBusMismatch, 9, 1, 1)),
               Contains("position 2 (configured there: 'Term 2 (EL2008)'"));
}

TEST_CASE("without the ENI and the plan, slaves and frames are named by number") {
    const EventDescriber bare{nullptr, nullptr};
    CHECK(bare.describe(event(events::kSlavePresence, 6, 2, 0)) ==
          "cycle 6: slave #3 (not in the ENI) is absent (no answer at its station address)");
    CHECK(bare.describe(event(events::kLineBreak, 8, 1, 1)) ==
          "cycle 8: line break after slave 1 (slaves reachable from MAIN: 1)");
    CHECK(bare.describe(event(events::kCyclicWkcError, 9, 0, 2, 1, 0)) ==
          "cycle 9: cyclic frame 1 datagram 3 came back with WKC 0, expected 1: the cycle's inputs are marked invalid");
    Event lost = event(events::kFrameLost, 10, static_cast<std::uint32_t>(FrameKind::Cyclic), 1);
    LostFrameDetail detail;
    detail.master_state = static_cast<std::uint8_t>(eni::SlaveState::Safeop);
    detail.sent_main = true;
    detail.encode_into(lost);
    CHECK(bare.describe(lost) ==
          "cycle 10: cyclic frame 2 (SAFEOP) lost (MAIN copy missing, RED copy not sent): this cycle's inputs keep "
          "their last values");
}

TEST_CASE("a cycle stall says how many deadlines passed, how late the cycle woke, and why") {
    Fixture f;
    CHECK(f.describer.describe(event(events::kCycleStall, 4567, 1099, 4)) ==
          "cycle 4567: 4 cycle deadline(s) passed without a cycle (it woke 1099 µs after its deadline and ended "
          "that much later): the machine did not run this master in time (other processes or the host), or the "
          "cycle ran that long; the skipped cycles sent nothing");
}
