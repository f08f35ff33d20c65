// DcStartup against the simulated segment of a real drive ENI: the ring's
// exit closed for the measurement and opened again, delays from the latches
// along the line, offsets that give every slave the reference's system time,
// the reference clock chosen among the candidates with a clear error when
// none can be, and a re-measurement that leaves the running slaves' offsets
// alone. ecsim's 0x092C and the master's reading of it agree on the sign.

#include <catch2/catch.hpp>

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/dc/dc_startup.hpp"
#include "ecpair/dc/deviation_monitor.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/sim/segment_bus_access.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

using namespace ecpair;

namespace {

namespace reg = wire::reg;

// Remembers what DcStartup asks of it; sends the static drift compensation
// through the bus, one ARMW per frame.
class RecordingHost final : public dc::DcHost {
public:
    explicit RecordingHost(bus::BusAccess& bus) : bus_(bus) {}
    void hold(bool held) override { holds.push_back(held); }
    void ring_opened(bool opened) override { openings.push_back(opened); }
    Expected<void, std::string> static_drift_compensation(std::uint16_t reference, std::uint32_t frames) override {
        for (std::uint32_t i = 0; i < frames; ++i) {
            bus::DatagramRequest armw;
            armw.command = wire::Command::Armw;
            armw.address =
                wire::DatagramHeader::physical(bus::SlaveAddress::position(reference).adp(), reg::kDcSystemTime);
            armw.data.assign(8, 0);
            if (auto r = bus_.exchange(armw); !r || r->wkc == 0) return unexpected(std::string("ARMW not answered"));
        }
        burst_frames += frames;
        return {};
    }
    void configured(const dc::DcSetup& s) override { setup = s; }

    std::vector<bool> holds, openings;
    std::uint32_t burst_frames = 0;
    std::optional<dc::DcSetup> setup;

private:
    bus::BusAccess& bus_;
};

// A BusAccess that notes every request on its way to the segment.
class LoggingBus final : public bus::BusAccess {
public:
    explicit LoggingBus(bus::BusAccess& inner) : inner_(inner) {}
    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override {
        requests.push_back(request);
        return inner_.exchange(request);
    }
    std::vector<bus::DatagramRequest> requests;

private:
    bus::BusAccess& inner_;
};

struct Fixture {
    std::shared_ptr<const eni::EniConfig> eni;
    sim::Segment segment;
    sim::SegmentBusAccess segment_bus;
    LoggingBus bus{segment_bus};
    RecordingHost host{bus};

    static std::shared_ptr<const eni::EniConfig> load(const char* name) {
        auto loaded = eni::load_eni_file(fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, name));
        REQUIRE(loaded);
        return *loaded;
    }
    static sim::Segment build(const eni::EniConfig& e) {
        auto s = sim::Segment::from_eni(e);
        REQUIRE(s);
        return std::move(s).value();
    }

    explicit Fixture(const char* name) : eni(load(name)), segment(build(*eni)), segment_bus(segment) {
        // The station addresses, as the slaves' INIT -> PREOP InitCmds set them.
        for (std::size_t p = 0; p < eni->slaves.size(); ++p) {
            REQUIRE(bus::write_register(segment_bus, bus::SlaveAddress::position(static_cast<std::uint16_t>(p)),
                                        reg::kStationAddress,
                                        {static_cast<std::uint8_t>(eni->slaves[p].info.phys_addr),
                                         static_cast<std::uint8_t>(eni->slaves[p].info.phys_addr >> 8)}));
        }
    }

    dc::DcRequest start_up() const {
        dc::DcRequest r;
        for (const auto& s : eni->slaves) r.candidates.push_back(s.info.phys_addr);
        r.static_frames = 25;
        return r;
    }
    std::uint64_t memory64(std::size_t position, std::uint16_t address) {
        return load_le<std::uint64_t>(segment.slave(position).read_memory(address, 8), 0);
    }
    std::uint32_t memory32(std::size_t position, std::uint16_t address) {
        return load_le<std::uint32_t>(segment.slave(position).read_memory(address, 4), 0);
    }
};

dc::DcStartupOptions fixed_clocks() {
    dc::DcStartupOptions options;
    options.wall_clock = [] { return 700'000'000'000'000'000ull; };
    return options;
}

}  // namespace

TEST_CASE("DC start-up on the Elmo ring: the exit closed, delays along the line, one system time", "[dc]") {
    Fixture f("ecengineer_rocos_elmo_4slaves.xml");
    dc::DcStartup startup(f.bus, f.host, fixed_clocks());
    const auto loop_before = f.segment.slave(4).read_memory(reg::kDlControlLoop, 1);

    const auto setup = startup.run(f.start_up());
    INFO((setup ? std::string("ok") : setup.error()));
    REQUIRE(setup);
    CHECK(setup->reference_position == 0);
    CHECK(setup->reference_station == 1001);
    REQUIRE(setup->slaves.size() == 4);

    // The exit (the last slave's port B towards RED) was closed, then given back its setting.
    bool closed = false;
    for (const auto& r : f.bus.requests) {
        if (r.command == wire::Command::Apwr && (r.address >> 16) == reg::kDlControlLoop &&
            (r.data[0] & 0x0C) == 0x0C) {
            closed = true;
        }
    }
    CHECK(closed);
    CHECK(f.segment.slave(4).read_memory(reg::kDlControlLoop, 1) == loop_before);
    CHECK(f.host.openings == std::vector<bool>{true, false});
    CHECK(f.host.holds == std::vector<bool>{true, false});

    // Delays grow along the line and are in the slaves' 0x0928.
    std::int64_t previous = -1;
    for (std::size_t p = 0; p < 4; ++p) {
        const auto& s = setup->slaves[p];
        REQUIRE(s.delay);
        CHECK(*s.delay > previous);
        previous = *s.delay;
        CHECK(f.memory32(p + 1, reg::kDcSystemTimeDelay) == static_cast<std::uint32_t>(*s.delay));
        CHECK(f.memory64(p + 1, reg::kDcSystemTimeOffset) == *s.offset);
    }
    CHECK(*setup->slaves[0].delay == 0);

    // The system time of every slave is the reference's: read in one frame,
    // each ESC takes its copy as the frame passes, one delay later.
    std::vector<bus::DatagramRequest> reads;
    for (std::uint16_t p = 0; p < 4; ++p)
        reads.push_back(bus::read_request(bus::SlaveAddress::position(p), reg::kDcSystemTime, 8));
    const auto times = f.segment_bus.exchange_all(reads);
    for (std::size_t p = 1; p < 4; ++p) {
        REQUIRE(times[p]);
        const auto t = static_cast<std::int64_t>(load_le<std::uint64_t>(times[p]->data, 0));
        // Each read is its own frame here: the slave's time at its own frame, the reference's at its.
        CHECK(t > static_cast<std::int64_t>(load_le<std::uint64_t>(times[0]->data, 0)));
    }
    // The reference's system time is the master's clock (since 2000) at the latch.
    CHECK(setup->reference_time >= 700'000'000'000'000'000ull);
    CHECK(setup->reference_time < 700'000'000'000'000'000ull + 1'000'000'000ull);
    CHECK(f.host.burst_frames == 25);
    CHECK(setup->static_frames == 25);
}

TEST_CASE("the reference clock among the candidates, and the error when there is none", "[dc]") {
    Fixture f("ecengineer_rocos_elmo_4slaves.xml");
    dc::DcStartup startup(f.bus, f.host, fixed_clocks());
    auto request = f.start_up();
    request.candidates = {999, 1002};
    const auto setup = startup.run(request);
    REQUIRE(setup);
    CHECK(setup->reference_position == 1);
    CHECK(*setup->slaves[1].delay == 0);
    CHECK_FALSE(setup->slaves[0].delay);  // the slave before the reference gets no delay
    CHECK(setup->slaves[0].why == "reached before the reference clock");

    request.candidates = {999};
    const auto none = startup.run(request);
    REQUIRE_FALSE(none);
    CHECK_THAT(none.error(),
               Catch::Contains("no DC-capable slave for the reference clock: station 999 is not on the bus"));
    CHECK(f.host.holds.back() == false);
}

TEST_CASE("a re-measurement gives offsets only to the slaves that join", "[dc]") {
    Fixture f("ecengineer_rocos_elmo_4slaves.xml");
    dc::DcStartup startup(f.bus, f.host, fixed_clocks());
    REQUIRE(startup.run(f.start_up()));
    // Slave 4 loses its offset (as a slave that was just powered on would have none).
    REQUIRE(bus::write_register(f.segment_bus, bus::SlaveAddress::position(3), reg::kDcSystemTimeOffset,
                                std::vector<std::uint8_t>(8, 0)));
    REQUIRE(f.memory64(4, reg::kDcSystemTimeOffset) == 0);
    const auto kept = f.memory64(2, reg::kDcSystemTimeOffset);

    auto request = f.start_up();
    request.start_up = false;
    request.joining = {1004};
    request.static_frames = 0;
    const auto again = startup.run(request);
    REQUIRE(again);
    CHECK(f.memory64(2, reg::kDcSystemTimeOffset) == kept);
    CHECK(f.memory64(4, reg::kDcSystemTimeOffset) != 0);
    CHECK(f.memory64(4, reg::kDcSystemTimeOffset) == *again->slaves[3].offset);
    CHECK(*again->slaves[1].offset == kept);
}

// The master (dc::SystemTimeDifference) and ecsim's ESC must read bit 31 of
// 0x092C the same way (dc-and-diagnosis-facts.md: set when the local copy is
// smaller than the received time): a flip on either side fails here.
namespace {

constexpr std::uint16_t kTimeDifferenceFilterDepth = 0x0934;

std::vector<std::uint8_t> le(std::uint64_t value, std::size_t length) {
    std::vector<std::uint8_t> bytes(length);
    for (std::size_t i = 0; i < length; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
    return bytes;
}

}  // namespace

TEST_CASE("0x092C: a slave behind the reference reads as behind, one ahead as ahead", "[dc]") {
    Fixture f("ecengineer_rocos_elmo_4slaves.xml");
    dc::DcStartup startup(f.bus, f.host, fixed_clocks());
    REQUIRE(startup.run(f.start_up()));
    const auto slave = bus::SlaveAddress::position(2);
    REQUIRE(bus::write_register(f.segment_bus, slave, kTimeDifferenceFilterDepth, {0}));  // 0x092C = the last Δt
    const auto delay_read = bus::read_register(f.segment_bus, slave, reg::kDcSystemTimeDelay, 4);
    const auto offset_read = bus::read_register(f.segment_bus, slave, reg::kDcSystemTimeOffset, 8);
    REQUIRE(delay_read);
    REQUIRE(offset_read);
    const auto delay = load_le<std::uint32_t>(delay_read->data, 0);
    const auto offset = load_le<std::uint64_t>(offset_read->data, 0);
    const auto difference_after_armw = [&] {
        bus::DatagramRequest armw;
        armw.command = wire::Command::Armw;
        armw.address = wire::DatagramHeader::physical(bus::SlaveAddress::position(0).adp(), reg::kDcSystemTime);
        armw.data.assign(8, 0);
        const auto sent = f.segment_bus.exchange(armw);
        REQUIRE(sent);
        CHECK(sent->wkc == 4);
        const auto read = bus::read_register(f.segment_bus, slave, reg::kDcSystemTimeDifference, 4);
        REQUIRE(read);
        return dc::SystemTimeDifference{load_le<std::uint32_t>(read->data, 0)};
    };

    // 1 ms more delay: the slave's system time is 1 ms behind the reference's.
    REQUIRE(bus::write_register(f.segment_bus, slave, reg::kDcSystemTimeDelay, le(delay + 1'000'000, 4)));
    const auto behind = difference_after_armw();
    INFO(fmt::format("0x092C behind: 0x{:08x}", behind.raw));
    CHECK(behind.local_behind());
    CHECK(behind.signed_ns() < -900'000);
    CHECK(behind.signed_ns() > -1'100'000);

    // The delay back, 1 ms more offset: ahead (less what the loop slewed out meanwhile).
    REQUIRE(bus::write_register(f.segment_bus, slave, reg::kDcSystemTimeDelay, le(delay, 4)));
    REQUIRE(bus::write_register(f.segment_bus, slave, reg::kDcSystemTimeOffset, le(offset + 1'000'000, 8)));
    const auto ahead = difference_after_armw();
    INFO(fmt::format("0x092C ahead: 0x{:08x}", ahead.raw));
    CHECK_FALSE(ahead.local_behind());
    CHECK(ahead.signed_ns() > 500'000);
    CHECK(ahead.signed_ns() < 1'100'000);
}
