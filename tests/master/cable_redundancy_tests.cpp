// Cable redundancy of the Master, cycle by cycle and deterministic: the
// Master sends on MAIN and RED, the test carries every copy through an
// in-process ecsim Segment (5 slaves in OP) and hands the returned copies
// back in an order of its choosing, or drops some. Covers a line break at
// every position of the ring (both master cables included), copies coming
// back out of order, and copies lost on one side.

#include <algorithm>
#include <array>
#include <functional>
#include <future>
#include <thread>
#include <map>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/link/memory_link.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/sequencer/run_without_cyclic_master.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/sim/segment_bus_access.hpp"
#include "ecpair/wire/esc_registers.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

constexpr std::uint32_t kSlaves = 5;
constexpr std::uint32_t kCounterBytes = 2;  // the simulated slave's inputs start with a frame counter

// A copy of a frame as it came back to the master.
struct ReturnedCopy {
    master::LinkRole arrived_on;
    std::vector<std::uint8_t> bytes;
};

// Where in the images a slave's looped-back outputs show up.
struct Loopback {
    std::uint32_t output_offset;
    std::uint32_t input_offset;
    std::uint32_t length;
};

// What the application saw in one cycle.
struct CycleRecord {
    bool inputs_valid = false;
    std::vector<std::uint8_t> inputs;
    std::vector<std::uint8_t> outputs;  // as written by this cycle's hook
};

class SteppedRing {
public:
    // Called with the returned copies of one cycle before they reach the master.
    using Delivery = std::function<void(std::vector<ReturnedCopy>&)>;

    SteppedRing()
        : eni_(generated_eni()),
          segment_(sim::Segment::from_eni(*eni_).value()),
          main_(link::MemoryWire::make_pair("m-main", mac(0x11), "sim-main", mac(0x21))),
          red_(link::MemoryWire::make_pair("m-red", mac(0x12), "sim-red", mac(0x22))) {
        bring_segment_to_op();
        master::MasterOptions options;
        options.cable_redundancy = true;
        master_ = master::Master::create(eni_, options, *main_.a, red_.a.get(), events_).value();
        master_->request_state(eni::SlaveState::Op);
        master_->set_cycle_hook([this](master::ProcessImage& image, const master::CycleInfo& info) {
            // Every slave's outputs change every cycle, so a stale or lost input shows.
            for (const auto& area : loopbacks_) {
                for (std::uint32_t i = 0; i < area.length; ++i) {
                    image.outputs()[area.output_offset + i] = static_cast<std::uint8_t>(info.cycle * 7 + area.output_offset + i);
                }
            }
            records_[info.cycle] = CycleRecord{info.inputs_valid, {image.inputs().begin(), image.inputs().end()},
                                               {image.outputs().begin(), image.outputs().end()}};
        });
        for (const auto& slave : eni_->slaves) {
            const auto& send = slave.process_data.send;
            const auto& recv = slave.process_data.recv;
            REQUIRE(send);
            REQUIRE(recv);
            loopbacks_.push_back({send->bit_start / 8, recv->bit_start / 8 + kCounterBytes,
                                  std::min(send->bit_length / 8, recv->bit_length / 8 - kCounterBytes)});
        }
    }

    // One cycle: the master processes what came back and sends; the segment
    // carries every copy; `delivery` may reorder or drop the returned copies.
    void cycle(const Delivery& delivery = {}) {
        now_ += 1ms;
        master_->run_cycle(now_);
        std::vector<ReturnedCopy> returned;
        carry_all(*main_.b, sim::Side::Main, returned);
        carry_all(*red_.b, sim::Side::Red, returned);
        if (delivery) delivery(returned);
        for (const auto& copy : returned) master_->on_frame(copy.arrived_on, copy.bytes, now_);
    }

    void cycles(int n, const Delivery& delivery = {}) {
        for (int i = 0; i < n; ++i) cycle(delivery);
    }

    // Position 0 is the MAIN cable, kSlaves the RED cable, k between them the cable after slave k.
    void set_break(std::uint32_t position, bool broken) {
        if (position == 0 || position == kSlaves) {
            const bool main_side = position == 0;
            (main_side ? *main_.wire : *red_.wire).set_link_up(!broken);
            segment_.set_side_link(main_side ? sim::Side::Main : sim::Side::Red, !broken);
            master_->set_link_state(main_side ? master::LinkRole::Main : master::LinkRole::Red, !broken);
            return;
        }
        REQUIRE((broken ? segment_.break_link_after(position) : segment_.repair_link_after(position)));
    }

    master::Master& master() { return *master_; }
    std::uint64_t current_cycle() const { return master_->cycle(); }

    // True when every slave's inputs in cycle `c` show the outputs written
    // in cycle c-2: sent in c-1's frame, the slave's application copies
    // them after that frame, and the LRD of the next frame reads them.
    bool loopback_holds(std::uint64_t c) const {
        const auto& now = records_.at(c);
        const auto& written = records_.at(c - 2);
        return std::all_of(loopbacks_.begin(), loopbacks_.end(), [&](const Loopback& area) {
            return std::equal(written.outputs.begin() + area.output_offset,
                              written.outputs.begin() + area.output_offset + area.length,
                              now.inputs.begin() + area.input_offset);
        });
    }
    bool inputs_valid(std::uint64_t c) const { return records_.at(c).inputs_valid; }

    std::vector<master::Event> events() {
        std::vector<master::Event> out;
        for (const auto& report : events_.pop_all(0ms)) out.push_back(report.event);
        return out;
    }

private:
    static std::shared_ptr<const eni::EniConfig> generated_eni() {
        sim::GeneratedEniOptions options;
        options.slaves = kSlaves;
        options.input_bytes = 8;
        options.output_bytes = 6;
        return eni::load_eni_string(sim::generate_eni(options), "generated.xml").value();
    }
    static wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

    void bring_segment_to_op() {
        sim::SegmentBusAccess bus(segment_);
        REQUIRE(sequencer::run_without_cyclic_master(eni_, bus, sequencer::MasterState::Op, std::chrono::seconds(60)) ==
                sequencer::MasterState::Op);
    }

    void carry_all(link::Link& far_end, sim::Side entry, std::vector<ReturnedCopy>& returned) {
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
        for (;;) {
            auto frame = far_end.try_receive(buffer);
            if (!frame || !frame->has_value()) return;
            std::size_t size = (*frame)->size;
            sim_time_ns_ += 10'000;
            const auto exit = segment_.carry(entry, buffer, size, sim_time_ns_);
            if (!exit) continue;
            // A copy leaving the segment by its MAIN side reaches the master's MAIN adapter.
            returned.push_back({*exit == sim::Side::Main ? master::LinkRole::Main : master::LinkRole::Red,
                                {buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(size)}});
        }
    }

    std::shared_ptr<const eni::EniConfig> eni_;
    sim::Segment segment_;
    link::MemoryWire::Ends main_;
    link::MemoryWire::Ends red_;
    master::EventQueue events_;
    std::unique_ptr<master::Master> master_;
    std::vector<Loopback> loopbacks_;
    std::map<std::uint64_t, CycleRecord> records_;
    link::Clock::time_point now_ = link::Clock::now();
    std::uint64_t sim_time_ns_ = 1'000'000'000;
};

// Every cycle from `first` to the current one had complete inputs that loop back the outputs.
void require_every_cycle_complete(const SteppedRing& ring, std::uint64_t first) {
    for (std::uint64_t c = first; c <= ring.current_cycle(); ++c) {
        INFO("cycle " << c);
        REQUIRE(ring.inputs_valid(c));
        REQUIRE(ring.loopback_holds(c));
    }
}

std::vector<master::EventKind> kinds(const std::vector<master::Event>& events) {
    std::vector<master::EventKind> out;
    for (const auto& e : events) {
        if (e.kind != master::events::kMasterStateChanged) out.push_back(e.kind);
    }
    return out;
}

}  // namespace

TEST_CASE("a closed ring: every cycle complete, inputs loop back the outputs", "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.cycles(20);
    require_every_cycle_complete(ring, 4);
    CHECK(ring.master().ring_state() == master::RingState::Closed);
    const auto stats = ring.master().stats();
    CHECK(stats.frames_lost == 0);
    CHECK(stats.cycles_incomplete == 0);
    CHECK(stats.wkc_errors == 0);
    CHECK(kinds(ring.events()).empty());
}

TEST_CASE("a line break at every position of a 5-slave ring loses no cycle and is raised, then its repair",
          "[master][cable_redundancy]") {
    const std::uint32_t position = GENERATE(range(0u, kSlaves + 1));
    INFO("break after position " << position << " (0 = MAIN cable, 5 = RED cable)");
    SteppedRing ring;
    ring.cycles(10);
    (void)ring.events();

    ring.set_break(position, true);
    ring.cycles(10);
    CHECK(ring.master().ring_state() == master::RingState::Broken);
    const auto at_break = ring.events();
    const auto break_event = std::find_if(at_break.begin(), at_break.end(),
                                          [](const master::Event& e) { return e.kind == master::events::kLineBreak; });
    REQUIRE(break_event != at_break.end());
    if (break_event->b == 1) CHECK(break_event->a == position);
    CHECK(std::none_of(at_break.begin(), at_break.end(),
                       [](const master::Event& e) { return e.kind == master::events::kFrameLost; }));

    ring.set_break(position, false);
    ring.cycles(10);
    CHECK(ring.master().ring_state() == master::RingState::Closed);
    const auto at_repair = kinds(ring.events());
    CHECK(std::count(at_repair.begin(), at_repair.end(), master::events::kLineRepaired) == 1);

    require_every_cycle_complete(ring, 4);
    const auto stats = ring.master().stats();
    CHECK(stats.frames_lost == 0);
    CHECK(stats.cycles_incomplete == 0);
    CHECK(stats.wkc_errors == 0);
}

TEST_CASE("a break whose first cycles cannot place it is raised again with its place", "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.cycles(10);
    (void)ring.events();
    ring.set_break(2, true);
    // The copies that come back by MAIN (the ones that count the slaves
    // before the break) are lost for two cycles, as when a link goes down
    // with frames on it.
    const auto drop_main = [](std::vector<ReturnedCopy>& copies) {
        copies.erase(std::remove_if(copies.begin(), copies.end(),
                                    [](const ReturnedCopy& c) { return c.arrived_on == master::LinkRole::Main; }),
                     copies.end());
    };
    ring.cycles(2, drop_main);
    ring.cycles(5);
    CHECK(ring.master().ring_state() == master::RingState::Broken);
    std::vector<master::Event> breaks;
    for (const auto& e : ring.events()) {
        if (e.kind == master::events::kLineBreak) breaks.push_back(e);
    }
    REQUIRE(!breaks.empty());
    // The last word on the break says where it is, and it is said once.
    CHECK(breaks.back().b == 1);
    CHECK(breaks.back().a == 2);
    CHECK(std::count_if(breaks.begin(), breaks.end(), [](const master::Event& e) { return e.b == 1; }) == 1);
}

TEST_CASE("copies coming back in any order give the same cycle", "[master][cable_redundancy]") {
    const bool broken = GENERATE(false, true);
    INFO((broken ? "ring broken after slave 2" : "ring closed"));
    SteppedRing ring;
    if (broken) ring.set_break(2, true);
    SECTION("reversed") {
        ring.cycles(20, [](std::vector<ReturnedCopy>& copies) { std::reverse(copies.begin(), copies.end()); });
    }
    SECTION("RED arrivals first") {
        ring.cycles(20, [](std::vector<ReturnedCopy>& copies) {
            std::stable_partition(copies.begin(), copies.end(),
                                  [](const ReturnedCopy& c) { return c.arrived_on == master::LinkRole::Red; });
        });
    }
    require_every_cycle_complete(ring, 4);
    const auto stats = ring.master().stats();
    CHECK(stats.frames_lost == 0);
    CHECK(stats.wkc_errors == 0);
}

TEST_CASE("a copy lost on one side", "[master][cable_redundancy]") {
    SteppedRing ring;
    const auto drop_arrivals_on = [](master::LinkRole role) {
        return [role](std::vector<ReturnedCopy>& copies) {
            std::erase_if(copies, [role](const ReturnedCopy& c) { return c.arrived_on == role; });
        };
    };
    ring.cycles(10);

    SECTION("closed ring, the unprocessed copy lost: nothing is missing") {
        ring.cycle(drop_arrivals_on(master::LinkRole::Main));
        ring.cycles(5);
        require_every_cycle_complete(ring, 4);
        CHECK(ring.master().stats().frames_lost == 0);
    }
    SECTION("closed ring, the processed copy lost: that cycle alone is incomplete and said so") {
        ring.cycle(drop_arrivals_on(master::LinkRole::Red));
        const std::uint64_t lost_cycle = ring.current_cycle();
        ring.cycles(5);
        CHECK_FALSE(ring.inputs_valid(lost_cycle + 1));
        require_every_cycle_complete(ring, lost_cycle + 2);
        CHECK(ring.master().stats().frames_lost > 0);
        const auto k = kinds(ring.events());
        CHECK(std::count(k.begin(), k.end(), master::events::kFrameLost) > 0);
    }
    SECTION("broken ring, the copy from the MAIN half lost: that cycle alone is incomplete") {
        ring.set_break(2, true);
        ring.cycles(5);
        ring.cycle(drop_arrivals_on(master::LinkRole::Main));
        const std::uint64_t lost_cycle = ring.current_cycle();
        ring.cycles(5);
        CHECK_FALSE(ring.inputs_valid(lost_cycle + 1));
        require_every_cycle_complete(ring, lost_cycle + 2);
        CHECK(ring.master().stats().frames_lost > 0);
    }
}

TEST_CASE("with the MAIN cable gone, auto-increment requests reach the slaves through RED at their positions",
          "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.cycles(50);
    ring.set_break(0, true);  // the MAIN cable (a dead partner's side after a failover)
    ring.cycles(20);
    for (std::uint16_t position = 0; position < kSlaves; ++position) {
        INFO("position " << position);
        bus::DatagramRequest request;
        request.command = wire::Command::Aprd;
        request.address = wire::DatagramHeader::physical(static_cast<std::uint16_t>(-position), wire::reg::kStationAddress);
        request.data.assign(2, 0);
        auto reply = std::async(std::launch::async, [&] { return ring.master().bus().exchange(request); });
        for (int i = 0; i < 500 && reply.wait_for(0ms) != std::future_status::ready; ++i) {
            ring.cycle();
            std::this_thread::sleep_for(200us);  // lets the requesting thread queue its request
        }
        const auto answer = reply.get();
        REQUIRE(answer);
        CHECK(answer->wkc == 1);
        CHECK(load_le<std::uint16_t>(answer->data, 0) == 1001 + position);  // the slave at that position
    }
}
