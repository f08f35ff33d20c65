// Distributed clocks of one ESC (datasheet I §9, II §2.15): the system time
// read and the comparison a written time feeds, the receive-time latches,
// offset and delay, the time control loop, the cyclic unit (SYNC0/SYNC1),
// and ESCs with a 32-bit DC or none. All in virtual time: a Line adds 100 ns
// per hop and keeps the simulation time, or a test hands one ESC frames at
// the times it chooses. Oscillators are exact and start at 0 unless a test
// sets one, so local time = simulation time.

#include <catch2/catch.hpp>

#include <cmath>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::uint64_t u64(const std::vector<std::uint8_t>& raw) { return load_le<std::uint64_t>(raw, 0); }
std::uint32_t u32(const std::vector<std::uint8_t>& raw) { return load_le<std::uint32_t>(raw, 0); }
std::uint16_t u16(const std::vector<std::uint8_t>& raw) { return load_le<std::uint16_t>(raw, 0); }
std::vector<std::uint8_t> le64(std::uint64_t value) {
    std::vector<std::uint8_t> out(8);
    store_le<std::uint64_t>(out, 0, value);
    return out;
}

constexpr std::uint16_t kFirst = 0x1001;
constexpr std::uint16_t kSecond = 0x1002;
constexpr std::uint16_t kThird = 0x1003;

// One ESC on its own, linked on port 0, handed frames at chosen times.
class Single {
public:
    explicit Single(EscDescription description = drive_description()) : esc(std::move(description)) {
        esc.set_physical_link(0, true);
    }
    // One datagram addressed to the ESC (APxx with ADP 0) at common time `t`; returns it as it came out.
    Datagram at(std::uint64_t t, Command command, std::uint16_t ado, std::vector<std::uint8_t> data) {
        Frame frame({physical(command, 0, ado, std::move(data))});
        auto view = frame.view();
        ++seq_;
        esc.frame_arrived_at_port(0, t, seq_);
        esc.process(view, FrameContext{t, seq_});
        return frame.datagram(0);
    }
    void write(std::uint64_t t, std::uint16_t ado, std::vector<std::uint8_t> data) {
        at(t, Command::Apwr, ado, std::move(data));
    }
    std::vector<std::uint8_t> read(std::uint64_t t, std::uint16_t ado, std::size_t length) {
        return at(t, Command::Aprd, ado, std::vector<std::uint8_t>(length, 0)).data;
    }

    Esc esc;

private:
    std::uint64_t seq_ = 0;
};

constexpr std::uint64_t kMs = 1'000'000;

}  // namespace

// ------------------------------------------------------------------ system time, latches

TEST_CASE("0x0910 reads the local copy of the system time as the frame passed the reference clock") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    std::uint64_t t = line.time_ns();
    Frame frame({physical_read(Command::Fprd, kFirst, 0x0910, 8), physical_read(Command::Fprd, kSecond, 0x0910, 8)});
    line.run(frame);
    CHECK(u64(frame.datagram(0).data) == t + 100);  // taken as the frame reached each processing unit
    CHECK(u64(frame.datagram(1).data) == t + 200);

    // local time + offset (0x0920) - system time delay (0x0928)
    line.fpwr(kFirst, 0x0920, le64(1'000'000'000));
    line.fpwr(kFirst, 0x0928, le32(250));
    t = line.time_ns();
    CHECK(u64(line.fprd(kFirst, 0x0910, 8)) == t + 100 + 1'000'000'000 - 250);
}

TEST_CASE("a write to 0x0910 is compared, not stored") {
    Single one;
    one.write(1 * kMs, 0x0910, le64(0));
    // One received time moves the clock by one speed counter step (0.012 ppm): nothing to see a µs later.
    CHECK(u64(one.read(1 * kMs + 1'000, 0x0910, 8)) == 1 * kMs + 1'000);
    CHECK(u32(one.read(1 * kMs + 2'000, 0x092C, 4)) == 1'000'000U);  // 1 ms ahead of 0: bit 31 clear
}

TEST_CASE("an oscillator's drift and power-on start show in the local time") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line[1].set_oscillator(Oscillator{100'000, 0});  // +100 ppm, started at 0
    line.advance(1'000'000'000);
    const std::uint64_t t = line.time_ns();
    Frame frame({physical_read(Command::Fprd, kFirst, 0x0910, 8), physical_read(Command::Fprd, kSecond, 0x0910, 8)});
    line.run(frame);
    CHECK(u64(frame.datagram(0).data) == t + 100);
    // 100 ppm of the time since its power-on at 0
    CHECK(static_cast<double>(u64(frame.datagram(1).data)) == Approx(static_cast<double>(t + 200) * 1.0001).margin(1));

    // A seed starts the local time elsewhere, and elsewhere again at the next power-on.
    Esc esc(drive_description());
    esc.set_oscillator(Oscillator{0, 42});
    const std::uint64_t first = esc.dc_system_time_at(0);
    CHECK(first != 0);
    CHECK(first < (std::uint64_t{1} << 32));
    esc.power_off();
    esc.power_on(5'000);
    CHECK(esc.dc_system_time_at(5'000) != first);
    Esc twin(drive_description());
    twin.set_oscillator(Oscillator{0, 42});
    CHECK(twin.dc_system_time_at(0) == first);  // the same seed, the same clock
}

TEST_CASE("BWR and FPWR to 0x0900 latch every port's receive time - other writes only the processing unit's") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    const std::uint64_t t = line.time_ns();
    Frame latch({physical(Command::Bwr, 0, 0x0900, le32(0))});
    line.run(latch);
    const std::uint64_t seq = line.last_frame_seq();
    CHECK(u32(line.fprd(kFirst, 0x0900, 4)) == static_cast<std::uint32_t>(t + 100));
    CHECK(u64(line.fprd(kFirst, 0x0918, 8)) == t + 100);
    CHECK(u32(line.fprd(kSecond, 0x0900, 4)) == static_cast<std::uint32_t>(t + 200));

    // The frame comes back through port 1 of the first slave later.
    line[0].frame_arrived_at_port(1, t + 500, seq);
    CHECK(u32(line.fprd(kFirst, 0x0904, 4)) == static_cast<std::uint32_t>(t + 500));
    // Another frame passing port 1 does not change the latch.
    line[0].frame_arrived_at_port(1, t + 900, seq + 100);
    CHECK(u32(line.fprd(kFirst, 0x0904, 4)) == static_cast<std::uint32_t>(t + 500));

    // FPWR latches for its own slave.
    const std::uint64_t t2 = line.time_ns();
    line.fpwr(kSecond, 0x0900, le32(0));
    CHECK(u32(line.fprd(kSecond, 0x0900, 4)) == static_cast<std::uint32_t>(t2 + 200));
    CHECK(u32(line.fprd(kFirst, 0x0900, 4)) == static_cast<std::uint32_t>(t + 100));

    // APWR to 0x0900 latches 0x0918 only (section II 2.15.1.1 / 2.15.1.5).
    Single one;
    one.write(3 * kMs, 0x0900, le32(0));
    CHECK(u64(one.read(4 * kMs, 0x0918, 8)) == 3 * kMs);
    CHECK(u32(one.read(4 * kMs, 0x0900, 4)) == 0);
}

TEST_CASE("a frame that came in by another port latches that port from before the processing unit") {
    // Port 0 closed: the frame from port 1 goes round through port 0's loopback into the processing unit.
    Single one;
    one.esc.set_physical_link(1, true);
    one.write(1'000, 0x0101, bytes({0x03}));  // port 0: loop closed
    Frame latch({physical(Command::Bwr, 0, 0x0900, le32(0))});
    auto view = latch.view();
    one.esc.frame_arrived_at_port(1, 5'000, 77);
    one.esc.process(view, FrameContext{5'000, 77});
    CHECK(u32(one.read(9'000, 0x0904, 4)) == 5'000);
    CHECK(u64(one.read(9'000, 0x0918, 8)) == 5'000);
}

// ------------------------------------------------------------------ the time control loop

TEST_CASE("ARMW on 0x0910 distributes the reference time - 0x092C codes the difference as the facts sheet does") {
    Line line({drive_description(), drive_description(), drive_description()});
    line.assign_station_addresses();
    for (const std::uint16_t s : {kFirst, kSecond, kThird}) line.fpwr(s, 0x0934, bytes({0}));  // mean = the last difference
    line.fpwr(kSecond, 0x0928, le32(100));
    line.fpwr(kThird, 0x0928, le32(300));
    CHECK(u32(line.fprd(kThird, 0x092C, 4)) == 0);  // nothing received yet: the reset value
    const std::uint64_t t = line.time_ns();
    const Datagram armw = line.transact(physical(Command::Armw, 0, 0x0910, std::vector<std::uint8_t>(8, 0)));
    CHECK(armw.wkc == 3);
    CHECK(u64(armw.data) == t + 100);  // the reference clock's system time
    // Bit 31 set: the local copy is smaller than the received time (dc-and-diagnosis-facts.md).
    CHECK(u32(line.fprd(kSecond, 0x092C, 4)) == 0U);                  // (t+200 - 100) - (t+100): equal
    CHECK(u32(line.fprd(kThird, 0x092C, 4)) == (0x80000000U | 100U));  // (t+300 - 300) - (t+100): 100 ns behind
    CHECK(u32(line.fprd(kFirst, 0x092C, 4)) == 0);             // the reference is read, not written
    CHECK(line[0].dc_counters().reference_reads == 1);
    CHECK(line[1].dc_counters().reference_reads == 0);
}

TEST_CASE("the loop compares the lower 32 bits of the received time") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line.fpwr(kSecond, 0x0934, bytes({0}));
    line.fpwr(kSecond, 0x0920, le64(std::uint64_t{7} << 32));  // differs from the reference in the upper half only
    line.transact(physical(Command::Frmw, kFirst, 0x0910, le32(0)));
    CHECK(u32(line.fprd(kSecond, 0x092C, 4)) == 100U);  // 100 ns ahead (bit 31 clear): the hop
}

TEST_CASE("0x092C is the mean difference of filter depth 0x0934 - a write to 0x0930 resets the loop") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    // Depth 4 (reset value): each new difference moves the mean by a sixteenth.
    line.transact(physical(Command::Frmw, kFirst, 0x0910, le32(0)));
    CHECK(u32(line.fprd(kSecond, 0x092C, 4)) == 100U);  // the first difference is the mean (ahead)
    CHECK(static_cast<std::int16_t>(u16(line.fprd(kSecond, 0x0932, 2))) == 1);  // ahead: one step slower
    line.fpwr(kSecond, 0x0928, le32(1'700));  // now 1600 ns behind
    line.transact(physical(Command::Frmw, kFirst, 0x0910, le32(0)));
    CHECK(u32(line.fprd(kSecond, 0x092C, 4)) == (0x80000000U | 6U));  // 100 + (-1600 - 100) / 16 = -6.25: local copy less
    CHECK(static_cast<std::int16_t>(u16(line.fprd(kSecond, 0x0932, 2))) == 0);

    line.fpwr(kSecond, 0x0930, le16(0x1000));
    CHECK(u32(line.fprd(kSecond, 0x092C, 4)) == 0);
    CHECK(u16(line.fprd(kSecond, 0x0932, 2)) == 0);
}

namespace {

// The datasheet's relation of the speed counter difference to the clock deviation.
double deviation_of(std::int32_t diff, std::int32_t start = 0x1000) {
    return static_cast<double>(diff) / (5.0 * (start + diff + 2) * (start - diff + 2));
}

// A reference and a slave `ppm` fast, the slave's offset and delay as a
// master sets them from a receive-time measurement, the filters reset.
struct Pair {
    explicit Pair(std::int64_t drift_ppb) : line({drive_description(), drive_description()}) {
        line.assign_station_addresses();
        line[1].set_oscillator(Oscillator{drift_ppb, 0});
        line.transact(physical(Command::Bwr, 0, 0x0900, le32(0)));
        const auto reference = u64(line.fprd(kFirst, 0x0918, 8));
        const auto slave = u64(line.fprd(kSecond, 0x0918, 8));
        line.fpwr(kSecond, 0x0928, le32(100));  // the hop
        line.fpwr(kSecond, 0x0920, le64(reference - slave + 100));
        line.fpwr(kSecond, 0x0930, le16(0x1000));
    }
    void armw() { line.transact(physical(Command::Armw, 0, 0x0910, le32(0))); }
    // The truth: the slave's system time minus the reference's, now.
    std::int64_t deviation() {
        const std::uint64_t t = line.time_ns();
        return static_cast<std::int64_t>(line[1].dc_system_time_at(t) - line[0].dc_system_time_at(t));
    }

    Line line;
};

}  // namespace

TEST_CASE("drift compensation: the loop takes a drifting slave onto the reference and holds it there") {
    Pair pair(50'000);  // 50 ppm fast
    // Without received times it runs away: 50 µs a second.
    pair.line.advance(1'000'000'000);
    CHECK(pair.deviation() == Approx(50'000).margin(100));

    Pair locked(50'000);
    // Static drift compensation: a burst, one ARMW every 20 µs, then every millisecond.
    for (int i = 0; i < 15'000; ++i) {
        locked.armw();
        locked.line.advance(20'000);
    }
    for (int i = 0; i < 2'000; ++i) {
        locked.armw();
        locked.line.advance(kMs);
    }
    CHECK(std::abs(locked.deviation()) < 20);
    const auto diff = static_cast<std::int16_t>(u16(locked.line.fprd(kSecond, 0x0932, 2)));
    CHECK(deviation_of(diff) * 1e6 == Approx(50.0).margin(0.5));  // 0x0932 shows the 50 ppm
    const std::uint32_t difference = u32(locked.line.fprd(kSecond, 0x092C, 4));
    CHECK((difference & 0x7FFFFFFFU) < 20);

    // The loop keeps the rate: a second without drift compensation costs well under a µs, not 50 µs
    // (the speed counter difference wobbles a few steps of ~0.045 ppm around its value).
    locked.line.advance(1'000'000'000);
    CHECK(std::abs(locked.deviation()) < 1'000);
}

TEST_CASE("the loop's rate stays within the speed counter's range however large the difference") {
    Single one;
    // Two received times 1 ms apart, both a whole second off: the clock slews at its limit.
    one.write(1 * kMs, 0x0910, le64(1 * kMs + 1'000'000'000));
    one.write(2 * kMs, 0x0910, le64(2 * kMs + 1'000'000'000));
    const std::uint64_t from = u64(one.read(3 * kMs, 0x0910, 8));
    const std::uint64_t to = u64(one.read(4 * kMs, 0x0910, 8));
    const double rate = static_cast<double>(to - from) / static_cast<double>(kMs);
    const double limit = deviation_of(0x1000 - 0x7F);  // ~763 ppm at the reset speed counter start
    CHECK(rate > 1.0);
    CHECK(rate == Approx(1.0 + limit).margin(2e-6));
}

// ------------------------------------------------------------------ the cyclic unit

TEST_CASE("SYNC0 starts at the start time and repeats every cycle of the local copy of the system time") {
    Single one;
    one.write(1 * kMs, 0x09A0, le32(1'000'000));
    one.write(1 * kMs, 0x0990, le64(5 * kMs));
    one.write(1 * kMs, 0x0981, bytes({0x03}));
    CHECK((one.read(2 * kMs, 0x0984, 1)[0] & 0x01) == 0x01);  // first pulse pending
    CHECK(u64(one.read(2 * kMs, 0x0990, 8)) == 5 * kMs);     // the next pulse

    const DcTruth truth = one.esc.dc_truth(20 * kMs + 500'000);
    CHECK(truth.sync0_running);
    REQUIRE(truth.last_sync0);
    CHECK(truth.last_sync0->system_ns == 20 * kMs);
    CHECK(truth.last_sync0->at_ns == 20 * kMs);
    REQUIRE(truth.previous_sync0);
    CHECK(truth.previous_sync0->at_ns == 19 * kMs);
    CHECK(truth.sync0_missed == 0);
    CHECK(truth.sync0_doubled == 0);
    CHECK((one.read(20 * kMs + 600'000, 0x0984, 1)[0] & 0x01) == 0);
    CHECK(u64(one.read(20 * kMs + 600'000, 0x0990, 8)) == 21 * kMs);

    // A fast oscillator reaches each edge early on the common time base.
    Single fast;
    fast.esc.set_oscillator(Oscillator{100'000, 0});
    fast.write(1 * kMs, 0x09A0, le32(1'000'000));
    fast.write(1 * kMs, 0x0990, le64(5 * kMs));
    fast.write(1 * kMs, 0x0981, bytes({0x03}));
    const DcTruth early = fast.esc.dc_truth(20 * kMs);
    REQUIRE(early.last_sync0);
    CHECK(early.last_sync0->system_ns == 20 * kMs);
    CHECK(static_cast<double>(early.last_sync0->at_ns) == Approx(20e6 / 1.0001).margin(1.0));
}

TEST_CASE("a start time in the past: never reached by a 64-bit DC, at once with the plausibility check") {
    Single late;
    late.write(10 * kMs, 0x09A0, le32(1'000'000));
    late.write(10 * kMs, 0x0990, le64(5 * kMs));
    late.write(10 * kMs, 0x0981, bytes({0x03}));
    CHECK_FALSE(late.esc.dc_truth(1'000 * kMs).last_sync0);
    CHECK((late.read(1'000 * kMs, 0x0984, 1)[0] & 0x01) == 0x01);  // still pending

    Single checked;
    checked.write(10 * kMs, 0x09A0, le32(1'000'000));
    checked.write(10 * kMs, 0x0990, le64(5 * kMs));
    checked.write(10'300'000, 0x0981, bytes({0x23}));  // plausibility check: outside the near future
    CHECK((checked.read(10'400'000, 0x0984, 1)[0] & 0x04) == 0x04);
    const DcTruth truth = checked.esc.dc_truth(12'500'000);
    REQUIRE(truth.previous_sync0);
    CHECK(truth.previous_sync0->at_ns == 11 * kMs);  // after the immediate pulse, on the start time's grid
    CHECK(truth.last_sync0->at_ns == 12 * kMs);
}

TEST_CASE("a 32-bit DC reaches a start time in the past after its turn-over") {
    EscDescription narrow = drive_description();
    narrow.dc = DcSupport::Dc32;
    Single one(narrow);
    one.write(10 * kMs, 0x09A0, le32(1'000'000));
    one.write(10 * kMs, 0x0990, le32(5 * kMs));
    one.write(10 * kMs, 0x0981, bytes({0x03}));
    CHECK_FALSE(one.esc.dc_truth(4'000 * kMs).last_sync0);
    const std::uint64_t wrap = std::uint64_t{1} << 32;
    const DcTruth truth = one.esc.dc_truth(wrap + 6 * kMs);
    REQUIRE(truth.last_sync0);
    CHECK(truth.last_sync0->at_ns == wrap + 6 * kMs);
    REQUIRE(truth.previous_sync0);
    CHECK(truth.previous_sync0->at_ns == wrap + 5 * kMs);
    // The 32-bit registers: the system time's and the start time's upper halves read 0.
    CHECK(u64(one.read(wrap + 7 * kMs, 0x0910, 8)) == 7 * kMs);
    one.write(wrap + 7 * kMs, 0x0900, le32(0));
    CHECK(u64(one.read(wrap + 7 * kMs, 0x0918, 8)) == wrap + 7 * kMs);  // the receive time keeps 64 bits
    CHECK(u64(one.read(wrap + 7'100'000, 0x0990, 8)) == 8 * kMs);
}

TEST_CASE("auto-activation by the start time - deactivation stops SYNC0") {
    Single one;
    one.write(1 * kMs, 0x09A0, le32(1'000'000));
    one.write(1 * kMs, 0x0981, bytes({0x0A}));  // SYNC0 + auto-activation
    CHECK_FALSE(one.esc.dc_truth(2 * kMs).sync0_running);
    one.write(2 * kMs, 0x0990, le64(4 * kMs));
    CHECK(one.read(2 * kMs, 0x0981, 1)[0] == 0x0B);
    CHECK(one.esc.dc_truth(6'500'000).last_sync0->at_ns == 6 * kMs);
    one.write(7'500'000, 0x0981, bytes({0x00}));
    const DcTruth stopped = one.esc.dc_truth(20 * kMs);
    CHECK_FALSE(stopped.sync0_running);
    CHECK(stopped.last_sync0->at_ns == 7 * kMs);  // the last pulse before it stopped
}

TEST_CASE("SYNC0 status follows the pulse length - SYNC1 follows SYNC0 by its cycle time") {
    Single one;  // pulse length 1000 x 10 ns from the SII
    one.write(1 * kMs, 0x09A0, le32(1'000'000));
    one.write(1 * kMs, 0x09A4, le32(300'000));
    one.write(1 * kMs, 0x0990, le64(5 * kMs));
    one.write(1 * kMs, 0x0981, bytes({0x07}));
    CHECK(one.read(6 * kMs + 5'000, 0x098E, 1)[0] == 1);   // within the 10 µs pulse
    CHECK(one.read(6 * kMs + 15'000, 0x098E, 1)[0] == 0);
    CHECK(u64(one.read(5'100'000, 0x0998, 8)) == 5'300'000);
    CHECK(u64(one.read(5'400'000, 0x0998, 8)) == 6'300'000);
    CHECK(one.read(5'305'000, 0x098F, 1)[0] == 1);

    // Acknowledge mode (pulse length 0): the signal stays until the PDI acknowledges it, which nothing does here.
    Single ack;
    ack.esc.write_memory(0x0982, le16(0));
    ack.write(1 * kMs, 0x09A0, le32(1'000'000));
    ack.write(1 * kMs, 0x0990, le64(5 * kMs));
    ack.write(1 * kMs, 0x0981, bytes({0x03}));
    CHECK(ack.read(4 * kMs, 0x098E, 1)[0] == 0);
    CHECK(ack.read(5'500'000, 0x098E, 1)[0] == 1);
}

TEST_CASE("an offset written while SYNC0 runs: edges doubled when the clock jumps forward, missed when it jumps back") {
    for (const bool forward : {true, false}) {
        Single one;
        one.write(1 * kMs, 0x09A0, le32(1'000'000));
        one.write(1 * kMs, 0x0990, le64(5 * kMs));
        one.write(1 * kMs, 0x0981, bytes({0x03}));
        const std::uint64_t jump = forward ? 2'500'000 : ~std::uint64_t{2'500'000} + 1;
        one.write(10'200'000, 0x0920, le64(jump));
        const DcTruth truth = one.esc.dc_truth(20 * kMs);
        if (forward) {
            // Pulses at 10.0, 10.2 (the jump passes 11 and 12 at once: 11 is missed) and 10.5 ms (13):
            // two too soon.
            CHECK(truth.sync0_doubled == 2);
            CHECK(truth.sync0_missed == 1);
        } else {
            // 10.0 ms, then 11 ms of system time again only at 13.5 ms: three cycles without a pulse.
            CHECK(truth.sync0_missed == 3);
            CHECK(truth.sync0_doubled == 0);
        }
        one.esc.reset_dc_counters();
        CHECK(one.esc.dc_truth(30 * kMs).sync0_missed == 0);
    }
}

TEST_CASE("a PDI-controlled cyclic unit ignores the master's writes") {
    Single one;
    one.write(1 * kMs, 0x0980, bytes({0x01}));
    one.write(1 * kMs, 0x0981, bytes({0x03}));
    CHECK(one.read(1 * kMs, 0x0981, 1)[0] == 0);
    CHECK_FALSE(one.esc.dc_truth(2 * kMs).sync0_running);
}

// ------------------------------------------------------------------ DC support

TEST_CASE("an ESC without DC: its DC registers read 0 and ignore writes, which still count") {
    EscDescription plain = io_description();
    plain.dc = DcSupport::None;
    Single one(plain);
    CHECK((u16(one.read(1'000, 0x0008, 2)) & 0x010C) == 0);  // no DC, no 64 bit, no enhanced activation
    CHECK(one.at(2'000, Command::Apwr, 0x0920, le64(12345)).wkc == 1);
    CHECK(u64(one.read(3'000, 0x0920, 8)) == 0);
    CHECK(u64(one.read(3'000, 0x0910, 8)) == 0);
    CHECK(u16(one.read(3'000, 0x0930, 2)) == 0);

    Single full;
    CHECK((u16(full.read(1'000, 0x0008, 2)) & 0x010C) == 0x010C);
    EscDescription narrow = drive_description();
    narrow.dc = DcSupport::Dc32;
    Single thin(narrow);
    CHECK((u16(thin.read(1'000, 0x0008, 2)) & 0x010C) == 0x0104);
    thin.write(2'000, 0x0920, le64(0x1'0000'0005));
    CHECK(u64(thin.read(3'000, 0x0920, 8)) == 5);  // the offset's upper half is not there
}

