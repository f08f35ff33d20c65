// Distributed clocks across a segment, in virtual time: the receive-time
// latches on lines, junctions and a broken ring entered from its far end,
// with the delays of cables and ESCs; the seeded oscillators; a master's
// whole DC start-up (delays, offsets, static and continuous drift
// compensation, SYNC0) as the datasheet describes it, against ecsim's truth;
// the report (`ecsim ctl dc`) and its reset.

#include <catch2/catch.hpp>

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <set>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sim/control_commands.hpp"
#include "ecpair/sim/segment.hpp"
#include "segment_fixtures.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

constexpr std::uint64_t kUs = 1'000;
constexpr std::uint64_t kMs = 1'000'000;
constexpr std::uint32_t kCable = 300;
constexpr std::uint32_t kEsc = 300;

std::vector<std::uint8_t> le(std::uint64_t value, std::size_t size) {
    std::vector<std::uint8_t> out(size);
    for (std::size_t i = 0; i < size; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * i));
    return out;
}

std::uint64_t value_of(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t value = 0;
    for (std::size_t i = bytes.size(); i-- > 0;) value = (value << 8) | bytes[i];
    return value;
}

SegmentOptions exact_clocks(std::uint32_t cable = kCable, std::uint32_t esc = kEsc) {
    SegmentOptions options;
    options.clocks.seed = 0;
    options.propagation = {cable, esc, esc};
    return options;
}

// A master in virtual time: one datagram per frame, sent at `now`, which then moves on by `gap`.
struct VirtualMaster {
    explicit VirtualMaster(Segment& s) : segment(s) {}

    Segment& segment;
    std::uint64_t now = 1'000 * kMs;
    std::uint64_t gap = 20 * kUs;
    std::optional<Side> last_exit;

    TestFrame send(Command command, std::uint32_t address, std::vector<std::uint8_t> data, Side entry = Side::Main) {
        TestFrame frame = ethercat_frame({DatagramSpec{command, address, std::move(data)}});
        last_exit = segment.carry(entry, frame.buffer, frame.size, now);
        now += gap;
        return frame;
    }
    void assign_stations(std::size_t count) {
        for (std::size_t k = 0; k < count; ++k) {
            send(Command::Apwr, DatagramHeader::physical(static_cast<std::uint16_t>(0x10000 - k), 0x0010),
                 le(0x1001 + k, 2));
        }
    }
    std::uint64_t read(std::size_t position, std::uint16_t ado, std::size_t size) {
        return value_of(data_of(send(Command::Fprd, DatagramHeader::physical(station(position), ado),
                                     std::vector<std::uint8_t>(size, 0))));
    }
    void write(std::size_t position, std::uint16_t ado, std::uint64_t value, std::size_t size) {
        send(Command::Fpwr, DatagramHeader::physical(station(position), ado), le(value, size));
    }
    void broadcast(std::uint16_t ado, std::uint64_t value, std::size_t size, Side entry = Side::Main) {
        send(Command::Bwr, DatagramHeader::physical(0, ado), le(value, size), entry);
    }
    static std::uint16_t station(std::size_t position) { return static_cast<std::uint16_t>(0x1000 + position); }
};

std::uint32_t latch(const Segment& segment, std::size_t position, int port) {
    return static_cast<std::uint32_t>(
        value_of(segment.slave(position).read_memory(static_cast<std::uint16_t>(0x0900 + 4 * port), 4)));
}
std::uint64_t epu_latch(const Segment& segment, std::size_t position) {
    return value_of(segment.slave(position).read_memory(0x0918, 8));
}

}  // namespace

// ------------------------------------------------------------------ latches on real topologies

TEST_CASE("latches along a line: each cable and each ESC adds its delay, the return passes every port 1") {
    auto segment = Segment::from_specs(line_specs(4), exact_clocks());
    REQUIRE(segment);
    segment->set_side_link(Side::Red, false);  // a line: the last slave's port B leads nowhere
    VirtualMaster master{*segment};
    const std::uint64_t t0 = master.now;
    master.broadcast(0x0900, 0, 4);
    REQUIRE(master.last_exit == Side::Main);
    // Out: slave k's port 0 one cable after slave k-1 let the frame out through its EPU.
    for (std::size_t k = 1; k <= 4; ++k) {
        CHECK(latch(*segment, k, 0) == t0 + kCable + (k - 1) * (kEsc + kCable));
        CHECK(epu_latch(*segment, k) == latch(*segment, k, 0));  // port 0 open: the EPU's time is port 0's
    }
    // Back: the last slave turns the frame round (port 1 closed), each port 1 sees it return.
    std::uint64_t back = t0 + kCable + 3 * (kEsc + kCable) + kEsc + kCable;
    for (std::size_t k = 3; k >= 1; --k) {
        CHECK(latch(*segment, k, 1) == back);
        back += kEsc + kCable;
    }
    // The datasheet's propagation delay between neighbours (t_P = t_F here): the true one-way delay.
    for (std::size_t k = 1; k <= 2; ++k) {
        const std::int64_t own = static_cast<std::int64_t>(latch(*segment, k, 1)) - latch(*segment, k, 0);
        const std::int64_t next = static_cast<std::int64_t>(latch(*segment, k + 1, 1)) - latch(*segment, k + 1, 0);
        CHECK((own - next) / 2 == kEsc + kCable);
    }
}

TEST_CASE("latches at a junction: the time behind each of its ports, in the order D, B, C") {
    // A 4-port junction J; A on its port D, B on port B, C on port C (each a line end).
    std::vector<SlaveSpec> specs{
        {test_slave("J", "YYYY"), 1001, std::nullopt, 0},
        {test_slave("A"), 1002, eni::PreviousPort{true, 'D', 1001}, 0},
        {test_slave("B"), 1003, eni::PreviousPort{true, 'B', 1001}, 0},
        {test_slave("C"), 1004, eni::PreviousPort{true, 'C', 1001}, 0},
    };
    auto segment = Segment::from_specs(std::move(specs), exact_clocks());
    REQUIRE(segment);
    segment->set_side_link(Side::Red, false);
    VirtualMaster master{*segment};
    const std::uint64_t t0 = master.now;
    master.broadcast(0x0900, 0, 4);
    REQUIRE(master.last_exit == Side::Main);
    const std::uint64_t j0 = t0 + kCable;
    // A branch that ends in one slave takes: out through J, a cable, through the slave, a cable back.
    const std::uint64_t branch = kEsc + kCable + kEsc + kCable;
    CHECK(latch(*segment, 1, 0) == j0);
    CHECK(latch(*segment, 1, 3) == j0 + branch);               // D first
    CHECK(latch(*segment, 1, 1) == j0 + 2 * branch);           // then B
    CHECK(latch(*segment, 1, 2) == j0 + 3 * branch);           // then C
    CHECK(latch(*segment, 2, 0) == j0 + kEsc + kCable);        // A
    CHECK(latch(*segment, 3, 0) == j0 + branch + kEsc + kCable);
    CHECK(latch(*segment, 4, 0) == j0 + 2 * branch + kEsc + kCable);
}

TEST_CASE("a broken ring entered at RED: the slaves behind the break latch the frame from the far end") {
    auto segment = Segment::from_specs(line_specs(4), exact_clocks());
    REQUIRE(segment);
    REQUIRE(segment->break_link_after(2));
    VirtualMaster master{*segment};
    const std::uint64_t t0 = master.now;
    master.broadcast(0x0900, 0, 4, Side::Red);
    REQUIRE(master.last_exit == Side::Red);
    // Slave 4: port 1 on the way in (before its EPU), port 0 on the way back (its EPU).
    const std::uint64_t in4 = t0 + kCable;
    const std::uint64_t in3 = in4 + kEsc + kCable;  // forwarded alongside slave 4's EPU
    CHECK(latch(*segment, 4, 1) == in4);
    // Slave 3 (port 0 closed by the break): the frame goes round into its EPU from port 1.
    CHECK(latch(*segment, 3, 1) == in3);
    CHECK(epu_latch(*segment, 3) == in3);
    CHECK(latch(*segment, 3, 0) == in3);  // no arrival at port 0: the EPU's time
    const std::uint64_t back4 = in3 + kEsc + kCable;
    CHECK(latch(*segment, 4, 0) == back4);
    CHECK(epu_latch(*segment, 4) == back4);
    // Slaves 1 and 2 never saw it.
    CHECK(latch(*segment, 1, 0) == 0);
    CHECK(latch(*segment, 2, 0) == 0);
}

TEST_CASE("per-ESC and per-port delays, and tP different from tF, show in the latches") {
    SegmentOptions options = exact_clocks(100, 200);
    options.propagation.processing_ns = 240;  // t_Diff = 40 ns
    auto segment = Segment::from_specs(line_specs(3), options);
    REQUIRE(segment);
    segment->set_side_link(Side::Red, false);
    EscDelays slow = EscDelays::uniform(200, 240);
    slow.processing_ns[1] = 1'000;  // slave 2 takes long to let frames out through port 1
    REQUIRE(segment->set_esc_delays(2, slow));
    VirtualMaster master{*segment};
    const std::uint64_t t0 = master.now;
    master.broadcast(0x0900, 0, 4);
    CHECK(latch(*segment, 1, 0) == t0 + 100);
    CHECK(latch(*segment, 2, 0) == t0 + 100 + 240 + 100);
    CHECK(latch(*segment, 3, 0) == t0 + 100 + 240 + 100 + 1'000 + 100);
    // The return: slave 3 turns it round through its EPU (t_P), the others forward it (t_F).
    CHECK(latch(*segment, 2, 1) == latch(*segment, 3, 0) + 240 + 100);
    CHECK(latch(*segment, 1, 1) == latch(*segment, 2, 1) + 200 + 100);
    REQUIRE_FALSE(segment->set_esc_delays(9, slow));
}

// ------------------------------------------------------------------ oscillators

TEST_CASE("every ESC's oscillator comes from the seed: drift within the bound, random power-on times") {
    SegmentOptions options;
    options.clocks = {25, 7};
    auto a = Segment::from_specs(line_specs(20), options);
    auto b = Segment::from_specs(line_specs(20), options);
    options.clocks.seed = 8;
    auto c = Segment::from_specs(line_specs(20), options);
    REQUIRE((a && b && c));
    const DcReport ra = a->dc_report();
    const DcReport rb = b->dc_report();
    const DcReport rc = c->dc_report();
    bool differs_from_other_seed = false;
    std::set<std::int64_t> drifts;
    for (std::size_t i = 0; i < 20; ++i) {
        const std::int64_t drift = ra.slaves[i].truth.drift_ppb;
        CHECK(std::abs(drift) <= 25'000);
        drifts.insert(drift);
        CHECK(drift == rb.slaves[i].truth.drift_ppb);  // the same seed, the same clocks
        CHECK(ra.slaves[i].truth.local_time_ns == rb.slaves[i].truth.local_time_ns);
        CHECK(ra.slaves[i].truth.local_time_ns < (std::uint64_t{1} << 32));
        differs_from_other_seed = differs_from_other_seed || drift != rc.slaves[i].truth.drift_ppb;
    }
    CHECK(drifts.size() > 15);
    CHECK(differs_from_other_seed);

    // A power cycle starts the local time anew.
    const std::uint64_t before = a->slave(3).dc_system_time_at(a->now_ns());
    REQUIRE(a->power_off(3));
    REQUIRE(a->power_on(3));
    CHECK(a->slave(3).dc_system_time_at(a->now_ns()) != before);

    // drift 0: exact rates, the local times still apart.
    options.clocks = {0, 9};
    auto d = Segment::from_specs(line_specs(3), options);
    REQUIRE(d);
    CHECK(d->dc_report().slaves[1].truth.drift_ppb == 0);
    CHECK(d->dc_report().slaves[0].truth.local_time_ns != d->dc_report().slaves[1].truth.local_time_ns);
}

// ------------------------------------------------------------------ a master's DC start-up against the truth

namespace {

// What the common masters do (dc-and-diagnosis-facts.md, datasheet I 9.1.3.6) on a line,
// the reference clock being slave 1; returns the delays written.
std::vector<std::uint64_t> start_dc(VirtualMaster& master, std::size_t count) {
    master.broadcast(0x0900, 0, 4);
    std::vector<std::uint64_t> t0(count + 1), t1(count + 1), epu(count + 1);
    for (std::size_t k = 1; k <= count; ++k) {
        t0[k] = master.read(k, 0x0900, 4);
        t1[k] = master.read(k, 0x0904, 4);
        epu[k] = master.read(k, 0x0918, 8);
    }
    // Time behind port 1, less the next slave's: twice the hop (t_P = t_F); the last returns at once.
    std::vector<std::uint64_t> delay(count + 1, 0);
    for (std::size_t k = 2; k <= count; ++k) {
        const auto behind = [&](std::size_t s) { return s > count ? 0 : static_cast<std::uint32_t>(t1[s] - t0[s]); };
        const std::uint64_t hop = (behind(k - 1) - (k == count ? 0 : behind(k))) / 2;
        delay[k] = delay[k - 1] + hop;
    }
    const std::uint64_t master_time = 26 * 365ULL * 86'400 * 1'000'000'000;  // about 2026, ns since 2000
    for (std::size_t k = 1; k <= count; ++k) {
        master.write(k, 0x0928, delay[k], 4);
        // The reference's system time is bound to the master's; each slave's to the reference's.
        master.write(k, 0x0920, master_time - epu[1] + (epu[1] - epu[k]) + delay[k], 8);
    }
    master.broadcast(0x0930, 0x1000, 2);  // reset the loops
    // Static drift compensation: 15 000 ARMW, one every 20 µs.
    for (int i = 0; i < 15'000; ++i) master.send(Command::Armw, DatagramHeader::physical(0, 0x0910), le(0, 8));
    return delay;
}

// Every cycle an ARMW on 0x0910 (the ENIs' "DC; ARMW; System Time Register"), cycles of 1 ms.
void run_cycles(VirtualMaster& master, int cycles) {
    master.gap = 1 * kMs;
    for (int i = 0; i < cycles; ++i) master.send(Command::Armw, DatagramHeader::physical(0, 0x0910), le(0, 4));
}

void start_sync0(VirtualMaster& master, std::size_t count) {
    master.gap = 20 * kUs;
    const std::uint64_t reference = master.read(1, 0x0910, 8);
    const std::uint64_t start = (reference / kMs + 20) * kMs;  // a cycle boundary 20 ms ahead
    for (std::size_t k = 1; k <= count; ++k) {
        master.write(k, 0x09A0, kMs, 4);
        master.write(k, 0x0990, start, 8);
        master.write(k, 0x0981, 0x03, 1);
    }
}

}  // namespace

TEST_CASE("a master that does what the datasheet says gets drifting slaves within tens of ns of the reference") {
    SegmentOptions options;
    options.clocks = {100, 3};  // 100 ppm, the bench figure
    auto segment = Segment::from_specs(line_specs(6), options);
    REQUIRE(segment);
    segment->set_side_link(Side::Red, false);
    VirtualMaster master{*segment};
    master.assign_stations(6);

    const DcReport unsynchronised = segment->dc_report();
    std::int64_t widest = 0;
    for (const auto& slave : unsynchronised.slaves) widest = std::max(widest, std::abs(*slave.deviation_ns));
    CHECK(widest > 1'000'000);  // power-on times apart by up to seconds

    const auto delays = start_dc(master, 6);
    // The measured delays are the true ones: 600 ns a hop.
    for (std::size_t k = 1; k <= 6; ++k) CHECK(static_cast<double>(delays[k]) == Approx((k - 1) * (kEsc + kCable)).margin(2));
    run_cycles(master, 1'000);
    start_sync0(master, 6);
    run_cycles(master, 1'000);

    const DcReport report = segment->dc_report();
    CHECK(report.reference == 1);
    CHECK(report.reference_from_master);  // the ARMW reads slave 1
    CHECK(report.synchronised == 6);
    CHECK(report.max_abs_deviation_ns < 30);
    REQUIRE(report.sync0_spread_ns);
    CHECK(*report.sync0_spread_ns < 30);
    CHECK(report.sync0_missed == 0);
    for (const auto& slave : report.slaves) {
        REQUIRE(slave.truth.last_sync0);
        CHECK(slave.truth.sync0_cycle_ns == kMs);
    }
    // 0x092C agrees: a BRD ORs them; every magnitude is small.
    for (std::size_t k = 2; k <= 6; ++k) CHECK((master.read(k, 0x092C, 4) & 0x7FFFFFFFU) < 30);
    // The reference's system time is the master's: about 2026.
    CHECK(master.read(1, 0x0910, 8) / 1'000'000'000 / 86'400 / 365 == 26);
}

TEST_CASE("the report follows a disturbance: worst deviation and SYNC0 edges missed until `dc reset`") {
    SegmentOptions options;
    options.clocks = {25, 11};
    auto segment = Segment::from_specs(line_specs(3), options);
    REQUIRE(segment);
    segment->set_side_link(Side::Red, false);
    VirtualMaster master{*segment};
    master.assign_stations(3);
    start_dc(master, 3);
    run_cycles(master, 500);
    start_sync0(master, 3);
    run_cycles(master, 100);
    segment->reset_dc_statistics();
    const DcReport calm = segment->dc_report();
    CHECK(calm.worst_deviation_ns < 30);
    CHECK(calm.sync0_missed == 0);

    // A master writes slave 3 a wrong offset: its system time jumps 2.5 cycles ahead.
    master.gap = 1 * kMs;
    const std::uint64_t offset = master.read(3, 0x0920, 8);
    master.write(3, 0x0920, offset + 2'500'000, 8);
    run_cycles(master, 5);
    const DcReport hit = segment->dc_report();
    CHECK(hit.worst_deviation_ns >= 2'400'000);
    CHECK(hit.sync0_missed >= 1);
    CHECK(hit.slaves[2].truth.sync0_missed + hit.slaves[2].truth.sync0_doubled >= 2);  // two edges jumped over
    CHECK(*hit.slaves[2].deviation_ns > 0);

    // Put right, and reset: the worst is the current figure again.
    master.write(3, 0x0920, offset, 8);
    run_cycles(master, 50);  // the loop slews out what it corrected meanwhile (763 ppm at most)
    segment->reset_dc_statistics();
    const DcReport after = segment->dc_report();
    CHECK(after.sync0_missed == 0);
    CHECK(after.worst_deviation_ns == after.max_abs_deviation_ns);
    CHECK(after.worst_deviation_ns < 1'000);
}

TEST_CASE("the report: powered-off and non-DC slaves, slaves without SYNC0 left out of the figures") {
    std::vector<SlaveSpec> specs = line_specs(3);
    specs[0].esc.dc = DcSupport::None;  // the first slave has no DC: the second is the reference
    auto segment = Segment::from_specs(std::move(specs));
    REQUIRE(segment);
    DcReport report = segment->dc_report();
    CHECK(report.reference == 2);
    CHECK_FALSE(report.reference_from_master);
    CHECK_FALSE(report.slaves[0].deviation_ns);
    CHECK(report.slaves[1].deviation_ns == 0);
    REQUIRE(report.slaves[2].deviation_ns);
    CHECK(report.synchronised == 0);
    CHECK(report.max_abs_deviation_ns == 0);  // nobody runs SYNC0
    CHECK_FALSE(report.sync0_spread_ns);

    REQUIRE(segment->power_off(2));
    report = segment->dc_report();
    CHECK(report.reference == 3);
    CHECK_FALSE(report.slaves[1].powered);
    CHECK_FALSE(report.slaves[1].deviation_ns);
}

TEST_CASE("an ENI's slave ahead of its reference clock without <DC> has no DC - the others have") {
    const auto config = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml"));
    REQUIRE(config);
    auto segment = Segment::from_eni(**config);
    REQUIRE(segment);
    CHECK(segment->slave(1).description().dc == DcSupport::None);  // "Imu": TwinCAT made slave 2 the reference
    for (std::size_t p = 2; p <= 5; ++p) CHECK(segment->slave(p).description().dc == DcSupport::Dc64);
    CHECK(segment->dc_report().reference == 2);

    const auto ring = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/advantech_io_ring_4slaves.xml"));
    REQUIRE(ring);
    auto advantech = Segment::from_eni(**ring);  // no <DC> anywhere, no reference: the ENI says nothing
    REQUIRE(advantech);
    for (std::size_t p = 1; p <= 4; ++p) CHECK(advantech->slave(p).description().dc == DcSupport::Dc64);
}

// ------------------------------------------------------------------ the control request

TEST_CASE("ecsim's dc request: text for people, JSON with the contract's names, reset") {
    auto segment = Segment::from_specs(line_specs(2));
    REQUIRE(segment);
    const std::string text = handle_control_line(*segment, "dc");
    CHECK(text.rfind("ok reference=slave 1 (the first DC slave) synchronised=0", 0) == 0);
    CHECK(text.find(" | 2 'S2' dc=64-bit deviation=") != std::string::npos);

    const std::string json = handle_control_line(*segment, "dc --json");
    REQUIRE(json.rfind("ok {", 0) == 0);
    google::protobuf::Struct parsed;
    REQUIRE(google::protobuf::util::JsonStringToMessage(json.substr(3), &parsed).ok());
    const auto& fields = parsed.fields();
    for (const char* name : {"max_abs_deviation_ns", "worst_deviation_ns", "sync0_spread_ns", "sync0_missed",
                             "reference", "slaves", "now_ns"}) {
        CHECK(fields.count(name) == 1);
    }
    CHECK(fields.at("reference").number_value() == 1);
    CHECK(fields.at("sync0_spread_ns").has_null_value());
    const auto& slaves = fields.at("slaves").list_value().values();
    REQUIRE(slaves.size() == 2);
    const auto& second = slaves[1].struct_value().fields();
    CHECK(second.at("name").string_value() == "S2");
    CHECK(second.at("dc").string_value() == "64-bit");
    CHECK(second.count("deviation_ns") == 1);
    CHECK(second.count("last_sync0_ns") == 1);

    CHECK(handle_control_line(*segment, "dc reset").rfind("ok ", 0) == 0);
    CHECK(handle_control_line(*segment, "dc now") == "error: dc: expected --json or reset, got 'now'");
    CHECK(handle_control_line(*segment, "dc --json reset").rfind("error: dc takes at most 1 argument", 0) == 0);
}
