// The segment's fast pass against the reference: the same frames carried
// through two segments built alike, one with the fast pass (frames pass the
// ESCs they do not address without calling them), one where every ESC on the
// path processes every frame. Both must give the same frames, the same exits
// and counters and, at the end, the same register files and process RAM in
// every ESC and the same clocks and SYNC0 pulses, through a master's start-up
// to OP, cyclic frames from both sides, line breaks, power cycles, an expired
// watchdog, loop settings written in the middle of a frame's route, and
// distributed clocks (latches from both ends, drift compensation, offsets).

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/cyclic_exchange.hpp"
#include "ecpair/sequencer/run_without_cyclic_master.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "segment_fixtures.hpp"

namespace {

using namespace ecpair;
using ecpair::test::DatagramSpec;
using ecpair::test::TestFrame;
using sim::Side;

sim::SegmentOptions without_fast_pass() {
    sim::SegmentOptions options;
    options.fast_pass = false;
    return options;
}

struct TwinSegments {
    explicit TwinSegments(const eni::EniConfig& config)
        : fast(sim::Segment::from_eni(config).value()),
          reference(sim::Segment::from_eni(config, without_fast_pass()).value()) {}

    // Carries a copy of `frame` through each; `frame` becomes the fast one's.
    std::optional<Side> carry(Side entry, TestFrame& frame, std::uint64_t time_step_ns = 100'000) {
        now_ns += time_step_ns;
        TestFrame copy = frame;
        const auto exit = fast.carry(entry, frame.buffer, frame.size, now_ns);
        const auto reference_exit = reference.carry(entry, copy.buffer, copy.size, now_ns);
        ++frames;
        if (exit != reference_exit || frame.size != copy.size ||
            !std::equal(frame.bytes().begin(), frame.bytes().end(), copy.bytes().begin())) {
            note(fmt::format("frame {} from {}: exit or bytes differ", frames, sim::to_string(entry)));
        }
        return exit;
    }

    void apply(const std::function<void(sim::Segment&)>& fault) {
        fault(fast);
        fault(reference);
    }

    void advance_time(std::uint64_t ns) {
        now_ns += ns;
        fast.advance_time(now_ns);
        reference.advance_time(now_ns);
    }

    // Every compared byte of every ESC, and the counters the two share.
    void compare_escs() {
        REQUIRE(fast.slave_count() == reference.slave_count());
        for (std::size_t position = 1; position <= fast.slave_count(); ++position) {
            const auto a = fast.slave(position).read_memory(0, 0x10000);
            const auto b = reference.slave(position).read_memory(0, 0x10000);
            for (std::size_t address = 0; address < a.size(); ++address) {
                if (a[address] != b[address]) {
                    note(fmt::format("slave {} byte {:#06x}: {:#04x} with the fast pass, {:#04x} without", position,
                                     address, a[address], b[address]));
                    break;
                }
            }
        }
        const auto& a = fast.counters();
        const auto& b = reference.counters();
        for (std::size_t side = 0; side < sim::kSideCount; ++side) {
            CHECK(a.sides[side].frames_in == b.sides[side].frames_in);
            CHECK(a.sides[side].frames_out == b.sides[side].frames_out);
        }
        CHECK(a.destroyed_circulating == b.destroyed_circulating);
        CHECK(a.lost_no_link == b.lost_no_link);
        CHECK(a.lost_closed_port == b.lost_closed_port);
        CHECK(b.epus_passed == 0);
        // The clocks: system times, SYNC0 pulses and the report's figures.
        const sim::DcReport ra = fast.dc_report();
        const sim::DcReport rb = reference.dc_report();
        CHECK(ra.reference == rb.reference);
        CHECK(ra.worst_deviation_ns == rb.worst_deviation_ns);
        CHECK(ra.sync0_missed == rb.sync0_missed);
        for (std::size_t i = 0; i < ra.slaves.size(); ++i) {
            const sim::DcTruth& x = ra.slaves[i].truth;
            const sim::DcTruth& y = rb.slaves[i].truth;
            const bool same_pulse = x.last_sync0.has_value() == y.last_sync0.has_value() &&
                                    (!x.last_sync0 || x.last_sync0->at_ns == y.last_sync0->at_ns);
            if (x.system_time_ns != y.system_time_ns || x.sync0_running != y.sync0_running || !same_pulse) {
                note(fmt::format("slave {}: DC clock or SYNC0 differ", i + 1));
            }
        }
    }

    void note(std::string difference) {
        if (differences++ == 0) first_difference = std::move(difference);
    }

    sim::Segment fast;
    sim::Segment reference;
    std::uint64_t now_ns = 1'000'000'000;
    std::size_t frames = 0;
    std::size_t differences = 0;
    std::string first_difference;
};

// A master's acyclic requests, one datagram per frame from MAIN, through both.
class TwinBus final : public bus::BusAccess {
public:
    explicit TwinBus(TwinSegments& twins) : twins_(twins) {}

    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override {
        std::lock_guard lock(mutex_);
        TestFrame frame = test::ethercat_frame({DatagramSpec{request.command, request.address, request.data}});
        if (!twins_.carry(Side::Main, frame)) return unexpected(bus::BusError{bus::BusErrc::Timeout, "died"});
        const auto view = wire::ConstFrameView::parse(frame.bytes());
        if (!view) return unexpected(bus::BusError{bus::BusErrc::Timeout, "unreadable"});
        const auto datagram = *view->begin();
        return bus::DatagramReply{{datagram.data().begin(), datagram.data().end()}, datagram.wkc(), datagram.irq()};
    }

private:
    TwinSegments& twins_;
    std::mutex mutex_;
};

// Generated slaves with a <DC> element each, so that every ESC has a clock.
std::shared_ptr<const eni::EniConfig> generated_eni(std::uint32_t slaves) {
    sim::GeneratedEniOptions options;
    options.slaves = slaves;
    auto config = std::make_shared<eni::EniConfig>(*eni::load_eni_string(sim::generate_eni(options), "generated.xml").value());
    for (auto& slave : config->slaves) slave.dc = eni::DistributedClocks{};
    return config;
}

void bring_to_op(const std::shared_ptr<const eni::EniConfig>& eni, TwinSegments& twins) {
    TwinBus bus(twins);
    REQUIRE(sequencer::run_without_cyclic_master(eni, bus, sequencer::MasterState::Op, std::chrono::seconds(60)) ==
            sequencer::MasterState::Op);
}

// The OP cyclic frames of one cycle with these outputs, carried from `entry`.
void run_cycle(TwinSegments& twins, master::CyclicExchange& exchange, std::uint8_t output_byte, Side entry) {
    std::vector<std::uint8_t> outputs(exchange.plan().output_image_size, output_byte);
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    for (std::size_t i = 0; i < exchange.frame_count(); ++i) {
        TestFrame frame;
        frame.size = exchange.build(i, eni::SlaveState::Op, outputs, ethernet, frame.buffer).size();
        twins.carry(entry, frame);
    }
}

}  // namespace

TEST_CASE("the fast pass gives the frames and ESCs every ESC processing every frame gives", "[segment][fast_pass]") {
    const auto eni = generated_eni(40);
    TwinSegments twins(*eni);
    bring_to_op(eni, twins);
    master::CyclicExchange exchange(master::CyclicPlan::build(*eni, {}).value());
    REQUIRE(exchange.frame_count() >= 4);

    const auto cycles = [&](int count, std::uint8_t first) {
        for (int c = 0; c < count; ++c) {
            const auto byte = static_cast<std::uint8_t>(first + c);
            run_cycle(twins, exchange, byte, Side::Main);
            run_cycle(twins, exchange, byte, Side::Red);  // the RED copies
        }
    };
    // Every ECAT event unmasked, so that the IRQ field of every datagram carries what each ESC has.
    TestFrame unmask = test::ethercat_frame(
        {DatagramSpec{wire::Command::Bwr, wire::DatagramHeader::physical(0, wire::reg::kEcatEventMask), {0xFF, 0xFF}}});
    twins.carry(Side::Main, unmask);
    cycles(50, 1);
    const std::uint64_t passed_in_op = twins.fast.counters().epus_passed;
    CHECK(passed_in_op > 0);  // the fast pass ran

    SECTION("a line break: each half processed from its own side, circulating bits on") {
        twins.apply([](sim::Segment& s) { REQUIRE(s.break_link_after(17)); });
        cycles(20, 60);
        twins.apply([](sim::Segment& s) { REQUIRE(s.repair_link_after(17)); });
        cycles(20, 90);
    }
    SECTION("a slave powered off and on again, then brought back by frames") {
        twins.apply([](sim::Segment& s) { REQUIRE(s.power_off(23)); });
        cycles(10, 60);
        twins.apply([](sim::Segment& s) { REQUIRE(s.power_on(23)); });
        cycles(10, 80);
    }
    SECTION("outputs stop: the watchdog expires in a frame's time and without frames") {
        twins.advance_time(50'000'000);
        TestFrame nop = test::ethercat_frame({DatagramSpec{wire::Command::Nop, 0, {0, 0}}});
        twins.carry(Side::Main, nop, 200'000'000);  // the watchdog expires as this frame passes
        CHECK(twins.fast.slave(40).al_status() == 0x14);  // SAFEOP + error (0x001B)
        CHECK((*wire::ConstFrameView::parse(nop.bytes()).value().begin()).irq() != 0);  // the AL status event
        twins.advance_time(300'000'000);  // and without frames
        cycles(10, 60);
    }
    SECTION("a frame closes a port of slave 30 in the middle of its route, and comes back to that port") {
        // RED down: the last slave loops the frames back, and they pass every slave twice. FPWR 0x0101
        // of slave 30 (station 1030): port B closed. Its ports change at the end of the frame's EPU
        // pass there; the frame leaves by the old ports and is lost coming back to the closed one. No
        // ESC behind slave 30 processes the frame (its LWR is for slave 1's outputs), so only the change
        // of slave 30's ports tells the carry that the rest of the recorded route no longer holds.
        twins.apply([](sim::Segment& s) { s.set_side_link(Side::Red, false); });
        for (int c = 0; c < 5; ++c) run_cycle(twins, exchange, static_cast<std::uint8_t>(c), Side::Main);
        const std::uint32_t loop = wire::DatagramHeader::physical(1030, wire::reg::kDlControlLoop);
        const std::uint32_t outputs_of_1 = 0x10000000;
        const std::vector<std::uint8_t> pattern(76, 0xA5);
        TestFrame close = test::ethercat_frame(
            {DatagramSpec{wire::Command::Fpwr, loop, {0x0C}}, DatagramSpec{wire::Command::Lwr, outputs_of_1, pattern}});
        CHECK_FALSE(twins.carry(Side::Main, close));
        for (int c = 0; c < 5; ++c) run_cycle(twins, exchange, static_cast<std::uint8_t>(c), Side::Main);
        const std::vector<std::uint8_t> zeros(76, 0);
        TestFrame reopen = test::ethercat_frame(
            {DatagramSpec{wire::Command::Fpwr, loop, {0x00}}, DatagramSpec{wire::Command::Lrd, outputs_of_1, zeros}});
        twins.carry(Side::Main, reopen);
        // The DC receive-time latch: every slave latches the frame's arrival at port A on the way out
        // and at port B on the way back.
        const std::uint32_t latch_all = wire::DatagramHeader::physical(0, wire::reg::kDcReceiveTimes);
        TestFrame latch = test::ethercat_frame({DatagramSpec{wire::Command::Bwr, latch_all, {0, 0, 0, 0}}});
        CHECK(twins.carry(Side::Main, latch) == Side::Main);
        twins.apply([](sim::Segment& s) { s.set_side_link(Side::Red, true); });
        cycles(5, 70);
    }
    SECTION("distributed clocks: latches from both ends of a broken ring, drift compensation, offsets, SYNC0") {
        using wire::Command;
        using wire::DatagramHeader;
        namespace reg = wire::reg;
        const auto broadcast = [&](Side entry, std::uint16_t ado, std::vector<std::uint8_t> data) {
            TestFrame frame = test::ethercat_frame({DatagramSpec{Command::Bwr, DatagramHeader::physical(0, ado), data}});
            twins.carry(entry, frame, 20'000);
        };
        const auto armw = [&](Side entry) {
            TestFrame frame = test::ethercat_frame(
                {DatagramSpec{Command::Nop, DatagramHeader::physical(0, reg::kDcReceiveTimes), {0, 0, 0, 0}},
                 DatagramSpec{Command::Armw, DatagramHeader::physical(0, reg::kDcSystemTime), {0, 0, 0, 0}}});
            twins.carry(entry, frame, 20'000);
        };
        twins.apply([](sim::Segment& s) { REQUIRE(s.break_link_after(17)); });
        broadcast(Side::Main, reg::kDcReceiveTimes, {0, 0, 0, 0});
        broadcast(Side::Red, reg::kDcReceiveTimes, {0, 0, 0, 0});
        for (const std::uint16_t station : {std::uint16_t{1005}, std::uint16_t{1030}}) {
            TestFrame offset = test::ethercat_frame({DatagramSpec{
                Command::Fpwr, DatagramHeader::physical(station, reg::kDcSystemTimeOffset), {0, 0, 0, 0, 1, 0, 0, 0}}});
            twins.carry(Side::Main, offset);
        }
        broadcast(Side::Main, reg::kDcSpeedCounterStart, {0x00, 0x10});
        broadcast(Side::Red, reg::kDcSpeedCounterStart, {0x00, 0x10});
        for (int i = 0; i < 200; ++i) {
            armw(Side::Main);
            armw(Side::Red);
        }
        broadcast(Side::Main, reg::kDcCycleTime0, {0x40, 0x42, 0x0F, 0x00});  // 1 ms
        broadcast(Side::Main, reg::kDcStartTime, {0, 0, 0, 0x80, 0, 0, 0, 0});
        broadcast(Side::Main, reg::kDcActivation, {0x23});  // at once, whatever the clock says
        for (int c = 0; c < 10; ++c) {
            run_cycle(twins, exchange, static_cast<std::uint8_t>(c), Side::Main);
            run_cycle(twins, exchange, static_cast<std::uint8_t>(c), Side::Red);
            armw(Side::Main);
            armw(Side::Red);
        }
        twins.apply([](sim::Segment& s) { REQUIRE(s.repair_link_after(17)); });
        cycles(5, 70);
    }
    SECTION("auto-increment datagrams among logical ones reach the slave their position names") {
        for (const int position : {1, 13, 40}) {
            const auto adp = static_cast<std::uint16_t>(1 - position);
            const std::uint32_t status = wire::DatagramHeader::physical(adp, wire::reg::kAlStatus);
            TestFrame frame = test::ethercat_frame(
                {DatagramSpec{wire::Command::Lrd, 0x10000000, std::vector<std::uint8_t>(40, 0)},
                 DatagramSpec{wire::Command::Aprd, status, {0, 0}}, DatagramSpec{wire::Command::Nop, 0, {0}}});
            twins.carry(Side::Main, frame);
            const auto view = wire::ConstFrameView::parse(frame.bytes()).value();
            auto datagram = view.begin();
            ++datagram;
            CHECK((*datagram).wkc() == 1);
        }
        cycles(5, 60);
    }
    twins.compare_escs();
    INFO("frames carried: " << twins.frames << ", first difference: " << twins.first_difference);
    CHECK(twins.differences == 0);
}
