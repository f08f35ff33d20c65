// Cable redundancy of the Master, cycle by cycle and deterministic: the
// Master sends on MAIN and RED, the test carries every copy through an
// in-process ecsim Segment (5 slaves in OP) and hands the returned copies
// back in an order of its choosing, or drops some. Covers a line break at
// every position of the ring (both master cables included), copies coming
// back out of order, copies lost on one side, and what the open-source
// redundancy suites test: both master cables cut and restored, one adapter
// failing to send while the other works, a start on a ring already broken,
// an LRW split into LWR + LRD under a break, a copy that comes again after
// its frame was answered, and DC receive times latched on a split ring.

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

// A master's adapter whose transmit path can fail while its carrier stays
// as the cable has it (a NIC that refuses to send).
class RefusingLink final : public link::Link {
public:
    explicit RefusingLink(link::Link& inner) : inner_(inner) {}
    void refuse(bool on) { refuse_ = on; }
    const std::string& name() const override { return inner_.name(); }
    wire::MacAddress mac() const override { return inner_.mac(); }
    Expected<void, link::LinkError> send(ConstBytes frame) override {
        if (refuse_) {
            return unexpected(link::LinkError{link::LinkErrc::SendFailed, inner_.name() + ": transmit failed"});
        }
        return inner_.send(frame);
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> try_receive(Bytes buffer) override {
        return inner_.try_receive(buffer);
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> receive(Bytes buffer,
                                                                          std::chrono::nanoseconds timeout) override {
        return inner_.receive(buffer, timeout);
    }
    int selectable_fd() const override { return inner_.selectable_fd(); }
    bool link_up() const override { return inner_.link_up(); }

private:
    link::Link& inner_;
    bool refuse_ = false;
};

class SteppedRing {
public:
    // Called with the returned copies of one cycle before they reach the master.
    using Delivery = std::function<void(std::vector<ReturnedCopy>&)>;

    // `before_start` runs on the segment once its slaves are in OP, before the master's first cycle.
    explicit SteppedRing(std::shared_ptr<const eni::EniConfig> eni = generated_eni(),
                         const std::function<void(SteppedRing&)>& before_start = {}, bool split_lrw = false)
        : eni_(std::move(eni)),
          segment_(sim::Segment::from_eni(*eni_).value()),
          main_(link::MemoryWire::make_pair("m-main", mac(0x11), "sim-main", mac(0x21))),
          red_(link::MemoryWire::make_pair("m-red", mac(0x12), "sim-red", mac(0x22))),
          main_adapter_(*main_.a),
          red_adapter_(*red_.a) {
        bring_segment_to_op();
        if (before_start) before_start(*this);
        master::MasterOptions options;
        options.cable_redundancy = true;
        options.split_lrw = split_lrw;
        master_ = master::Master::create(eni_, options, main_adapter_, &red_adapter_, events_).value();
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
        if (position == 0 || position == slave_count()) {
            const bool main_side = position == 0;
            (main_side ? *main_.wire : *red_.wire).set_link_up(!broken);
            segment_.set_side_link(main_side ? sim::Side::Main : sim::Side::Red, !broken);
            if (master_) master_->set_link_state(main_side ? master::LinkRole::Main : master::LinkRole::Red, !broken);
            return;
        }
        REQUIRE((broken ? segment_.break_link_after(position) : segment_.repair_link_after(position)));
    }
    std::uint32_t slave_count() const { return static_cast<std::uint32_t>(eni_->slaves.size()); }
    // The adapter's transmit fails (its carrier stays).
    void refuse_sends(master::LinkRole role, bool refuse) {
        (role == master::LinkRole::Main ? main_adapter_ : red_adapter_).refuse(refuse);
    }
    sim::Segment& segment() { return segment_; }

    // An acyclic exchange, with cycles run until it is answered.
    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) {
        auto reply = std::async(std::launch::async, [&] { return master().bus().exchange(request); });
        for (int i = 0; i < 500 && reply.wait_for(0ms) != std::future_status::ready; ++i) {
            cycle();
            std::this_thread::sleep_for(200us);  // lets the requesting thread queue its request
        }
        return reply.get();
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

    static std::shared_ptr<const eni::EniConfig> generated() { return generated_eni(); }

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
    RefusingLink main_adapter_;
    RefusingLink red_adapter_;
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

namespace {

// The generated 5-slave ENI with its LWR + LRD turned into one LRW over the same range (the
// slaves' inputs and outputs share their logical addresses, as many masters lay them out).
std::shared_ptr<const eni::EniConfig> lrw_eni() {
    sim::GeneratedEniOptions options;
    options.slaves = kSlaves;
    options.input_bytes = 8;
    options.output_bytes = 8;
    auto xml = sim::generate_eni(options);
    // The LWR becomes the LRW (read 1 + write 2 per slave); the LRD goes.
    const auto lwr = xml.find("<Comment>PD; LWR</Comment>");
    REQUIRE(lwr != std::string::npos);
    const auto code = xml.find("<Cmd>11</Cmd>", lwr);
    REQUIRE(code != std::string::npos);
    xml.replace(code, std::string("<Cmd>11</Cmd>").size(), "<Cmd>12</Cmd>");
    const auto count = xml.find("<Cnt>5</Cnt>", code);
    REQUIRE(count != std::string::npos);
    xml.replace(count, std::string("<Cnt>5</Cnt>").size(), "<Cnt>15</Cnt>");
    const auto lrd = xml.find("<Comment>PD; LRD</Comment>");
    REQUIRE(lrd != std::string::npos);
    const auto begin = xml.rfind("<Cmd>", lrd);
    const std::string close = "</Cmd>";
    const auto end = xml.find(close, xml.find("<OutputOffs>", lrd)) + close.size();
    xml.erase(begin, end - begin);
    auto eni = eni::load_eni_string(xml, "lrw.xml");
    INFO((eni ? std::string() : eni.error().describe()));
    REQUIRE(eni);
    REQUIRE((*eni)->uses_logical_read_write());
    return *eni;
}

bool raised(const std::vector<master::Event>& events, master::EventKind kind) {
    return std::any_of(events.begin(), events.end(), [kind](const master::Event& e) { return e.kind == kind; });
}

}  // namespace

TEST_CASE("both master cables cut and restored: nothing comes back meanwhile, then every cycle again",
          "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.cycles(10);
    (void)ring.events();
    ring.set_break(0, true);
    ring.set_break(kSlaves, true);
    ring.cycles(5);
    const std::uint64_t cut = ring.current_cycle();
    const auto stats_cut = ring.master().stats();
    CHECK(stats_cut.frames_lost > 0);
    CHECK(stats_cut.cycles_incomplete > 0);
    CHECK_FALSE(ring.inputs_valid(cut));  // no inputs made up while nothing came back
    const auto at_cut = ring.events();
    CHECK(raised(at_cut, master::events::kFrameLost));

    ring.set_break(0, false);
    ring.set_break(kSlaves, false);
    ring.cycles(10);
    CHECK(ring.master().ring_state() == master::RingState::Closed);
    require_every_cycle_complete(ring, ring.current_cycle() - 6);
    // Acyclic requests work again, on either side of the ring.
    bus::DatagramRequest brd;
    brd.command = wire::Command::Brd;
    brd.address = wire::DatagramHeader::physical(0, wire::reg::kType);
    brd.data.assign(2, 0);
    const auto reply = ring.exchange(brd);
    REQUIRE(reply);
    CHECK(reply->wkc == kSlaves);
}

TEST_CASE("one adapter fails to send while the other works", "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.cycles(10);
    (void)ring.events();

    SECTION("RED refuses: the MAIN copy passes every slave, no cycle is lost") {
        ring.refuse_sends(master::LinkRole::Red, true);
        ring.cycles(10);
        require_every_cycle_complete(ring, 4);
        CHECK(ring.master().stats().frames_lost == 0);
        CHECK(ring.master().stats().send_errors > 0);
    }
    SECTION("MAIN refuses with its carrier up: RED's copy passes the ring unprocessed, the loss is said") {
        ring.refuse_sends(master::LinkRole::Main, true);
        ring.cycles(5);
        const std::uint64_t refused = ring.current_cycle();
        CHECK_FALSE(ring.inputs_valid(refused));
        CHECK(ring.master().stats().cycles_incomplete > 0);
        CHECK(raised(ring.events(), master::events::kFrameLost));
        ring.refuse_sends(master::LinkRole::Main, false);
        ring.cycles(6);
        require_every_cycle_complete(ring, ring.current_cycle() - 3);
    }
    SECTION("MAIN refuses because its cable is gone: RED's copy is processed from slave 1 on, no cycle lost") {
        ring.refuse_sends(master::LinkRole::Main, true);
        ring.set_break(0, true);
        const std::uint64_t from = ring.current_cycle() + 2;
        ring.cycles(10);
        require_every_cycle_complete(ring, from);
    }
}

TEST_CASE(
    "a master starting on a ring already broken: cycles complete, the break raised once with its place, "
    "auto-increment requests reach both halves",
    "[master][cable_redundancy]") {
    SteppedRing ring(SteppedRing::generated(), [](SteppedRing& r) { r.set_break(3, true); });
    ring.cycles(10);
    CHECK(ring.master().ring_state() == master::RingState::Broken);
    require_every_cycle_complete(ring, 4);
    CHECK(ring.master().stats().frames_lost == 0);
    std::vector<master::Event> breaks;
    for (const auto& e : ring.events()) {
        if (e.kind == master::events::kLineBreak) breaks.push_back(e);
    }
    REQUIRE(!breaks.empty());
    CHECK(breaks.back().a == 3);
    CHECK(breaks.back().b == 1);
    for (std::uint16_t position = 0; position < kSlaves; ++position) {
        INFO("position " << position);
        bus::DatagramRequest request;
        request.command = wire::Command::Aprd;
        request.address =
            wire::DatagramHeader::physical(static_cast<std::uint16_t>(-position), wire::reg::kStationAddress);
        request.data.assign(2, 0);
        const auto answer = ring.exchange(request);
        REQUIRE(answer);
        CHECK(answer->wkc == 1);
        CHECK(load_le<std::uint16_t>(answer->data, 0) == 1001 + position);
    }
}

TEST_CASE("an LRW split into LWR + LRD under a break: every slave's inputs, from whichever half",
          "[master][cable_redundancy]") {
    SteppedRing ring(lrw_eni(), {}, /*split_lrw=*/true);
    ring.cycles(10);
    ring.set_break(2, true);
    ring.cycles(10);
    ring.set_break(2, false);
    ring.set_break(4, true);
    ring.cycles(10);
    require_every_cycle_complete(ring, 4);
    const auto stats = ring.master().stats();
    CHECK(stats.frames_lost == 0);
    CHECK(stats.wkc_errors == 0);
}

TEST_CASE("a copy that comes again after its frame was answered changes nothing", "[master][cable_redundancy]") {
    const bool broken = GENERATE(false, true);
    INFO((broken ? "ring broken after slave 2" : "ring closed"));
    SteppedRing ring;
    if (broken) ring.set_break(2, true);
    ring.cycles(10);
    std::vector<ReturnedCopy> previous;
    // Each cycle the copies of the cycle before come again, after this cycle's own: late duplicates.
    ring.cycles(10, [&previous](std::vector<ReturnedCopy>& copies) {
        const auto now = copies;
        copies.insert(copies.end(), previous.begin(), previous.end());
        previous = now;
    });
    // And a copy twice within its own cycle.
    ring.cycles(5, [](std::vector<ReturnedCopy>& copies) {
        const auto twice = copies;
        copies.insert(copies.end(), twice.begin(), twice.end());
    });
    require_every_cycle_complete(ring, 4);
    const auto stats = ring.master().stats();
    CHECK(stats.frames_lost == 0);
    CHECK(stats.wkc_errors == 0);
    CHECK(stats.late_frames > 0);  // counted, and never taken for a newer frame's answer
}

TEST_CASE("DC receive times on a split ring: every slave latches, each reads back its own times",
          "[master][cable_redundancy]") {
    SteppedRing ring;
    ring.set_break(2, true);
    ring.cycles(10);
    // Latch: a BWR to 0x0900 makes every slave, on both halves, note when the frame passed its ports.
    bus::DatagramRequest latch;
    latch.command = wire::Command::Bwr;
    latch.address = wire::DatagramHeader::physical(0, wire::reg::kDcReceiveTimes);
    latch.data.assign(4, 0);
    const auto latched = ring.exchange(latch);
    REQUIRE(latched);
    CHECK(latched->wkc == kSlaves);
    std::vector<std::vector<std::uint8_t>> latches;
    for (std::uint16_t i = 0; i < kSlaves; ++i) {
        INFO("station " << 1001 + i);
        bus::DatagramRequest read;
        read.command = wire::Command::Fprd;
        read.address = wire::DatagramHeader::physical(static_cast<std::uint16_t>(1001 + i), wire::reg::kDcReceiveTimes);
        read.data.assign(16, 0);
        const auto times = ring.exchange(read);
        REQUIRE(times);
        CHECK(times->wkc == 1);
        // The slave's own latches, not the zeros the master sent (which the other half carries back).
        CHECK(std::any_of(times->data.begin(), times->data.end(), [](std::uint8_t b) { return b != 0; }));
        latches.push_back(times->data);
    }
    // Every slave latched its own moments.
    std::sort(latches.begin(), latches.end());
    CHECK(std::adjacent_find(latches.begin(), latches.end()) == latches.end());
}
