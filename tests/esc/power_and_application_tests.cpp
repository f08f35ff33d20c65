// Power cycles and the PDI-side application (inputs follow outputs).

#include <catch2/catch.hpp>

#include "ecpair/wire/fmmu_config.hpp"
#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::vector<std::uint8_t> fmmu(std::uint32_t logical, std::uint16_t length, std::uint16_t physical, bool read) {
    wire::FmmuConfig config;
    config.logical_start = logical;
    config.length = length;
    config.physical_start = physical;
    config.read = read;
    config.write = !read;
    config.active = true;
    std::vector<std::uint8_t> encoded(wire::FmmuConfig::kSize);
    config.encode(encoded);
    return encoded;
}

// A drive with outputs at logical 0x1000 (6 bytes) and inputs at 0x1006 (8 bytes).
Line mapped_drive(std::uint8_t state) {
    Line line({drive_description()});
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0600, fmmu(0x1000, 6, 0x1100, false));
    line.fpwr(kFirstStation, 0x0610, fmmu(0x1006, 8, 0x1180, true));
    REQUIRE(bring_drive_to(line, kFirstStation, state) == state);
    return line;
}

std::vector<std::uint8_t> lrw(Line& line, const std::vector<std::uint8_t>& outputs, std::uint16_t* wkc = nullptr) {
    auto data = outputs;
    data.resize(14, 0);
    const Datagram d = line.transact(logical(Command::Lrw, 0x1000, data));
    if (wkc != nullptr) *wkc = d.wkc;
    return {d.data.begin() + 6, d.data.end()};
}

std::uint16_t counter_of(const std::vector<std::uint8_t>& inputs) {
    return static_cast<std::uint16_t>(inputs[0] | (inputs[1] << 8));
}

}  // namespace

TEST_CASE("power off: frames die and the ports close - power on: registers reset, the SII is kept") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    line.fpwr(0x1001, 0x0F80, bytes({0x42}));
    const auto last_word = static_cast<std::uint16_t>(line[0].sii_image().size() / 2 - 1);
    line.fpwr(0x1001, 0x0508, le16(0xCAFE));
    line.fpwr(0x1001, 0x0502, {0x01, 0x02, static_cast<std::uint8_t>(last_word), static_cast<std::uint8_t>(last_word >> 8), 0, 0});

    line[0].power_off();
    CHECK_FALSE(line[0].powered());
    CHECK_FALSE(line[0].port_open(0));
    CHECK_FALSE(line[0].port_open(1));
    CHECK(line[0].process_non_ethercat() == EpuVerdict::Destroy);
    Frame frame({physical_read(Command::Brd, 0, 0, 1)});
    CHECK_FALSE(line.run(frame));

    line[0].power_on();
    CHECK(line[0].powered());
    CHECK(line[0].port_open(0));
    CHECK(line[0].station_address() == 0);
    CHECK(line[0].al_status() == 0x01);
    CHECK(line[0].read_memory(0x0F80, 1) == bytes({0}));
    CHECK(load_le<std::uint16_t>(line[0].sii_image(), 2U * last_word) == 0xCAFE);
    Frame again({physical_read(Command::Brd, 0, 0, 1)});
    CHECK(line.run(again));
    CHECK(again.datagram(0).wkc == 2);
}

TEST_CASE("in SAFEOP the inputs carry a frame counter and no outputs") {
    Line line = mapped_drive(0x04);
    std::uint16_t wkc = 0;
    const auto first = lrw(line, bytes({1, 2, 3, 4, 5, 6}), &wkc);
    CHECK(wkc == 3);
    const auto second = lrw(line, bytes({1, 2, 3, 4, 5, 6}));
    CHECK(counter_of(second) == static_cast<std::uint16_t>(counter_of(first) + 1));
    CHECK(std::vector<std::uint8_t>(second.begin() + 2, second.end()) == bytes({0, 0, 0, 0, 0, 0}));
}

TEST_CASE("in OP the inputs mirror the outputs of the previous frame") {
    Line line = mapped_drive(0x08);
    lrw(line, bytes({1, 2, 3, 4, 5, 6}));
    const auto inputs = lrw(line, bytes({7, 8, 9, 10, 11, 12}));
    CHECK(std::vector<std::uint8_t>(inputs.begin() + 2, inputs.end()) == bytes({1, 2, 3, 4, 5, 6}));
    const auto next = lrw(line, bytes({0, 0, 0, 0, 0, 0}));
    CHECK(std::vector<std::uint8_t>(next.begin() + 2, next.end()) == bytes({7, 8, 9, 10, 11, 12}));
    CHECK(counter_of(next) == static_cast<std::uint16_t>(counter_of(inputs) + 1));
}

TEST_CASE("the application is deterministic: the same frames give the same inputs") {
    Line a = mapped_drive(0x08);
    Line b = mapped_drive(0x08);
    for (int i = 0; i < 5; ++i) {
        const auto outputs = bytes({i, i + 1, i + 2, i + 3, i + 4, i + 5});
        CHECK(lrw(a, outputs) == lrw(b, outputs));
    }
}

TEST_CASE("a power cycle restarts the counter") {
    Line fresh = mapped_drive(0x04);
    const std::uint16_t fresh_counter = counter_of(lrw(fresh, {}));

    Line line = mapped_drive(0x04);
    for (int i = 0; i < 10; ++i) lrw(line, {});
    line[0].power_off();
    line[0].power_on();
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0600, fmmu(0x1000, 6, 0x1100, false));
    line.fpwr(kFirstStation, 0x0610, fmmu(0x1006, 8, 0x1180, true));
    REQUIRE(bring_drive_to(line, kFirstStation, 0x04) == 0x04);
    CHECK(counter_of(lrw(line, {})) == fresh_counter);
}

TEST_CASE("inputs on a single-buffered (mailbox-mode, 0x22) SyncManager are marked full for every LRD, "
          "outputs on one are taken and emptied for every LWR") {
    // As a TwinCAT export for an Omron drive has it: SM3 in mailbox mode (control 0x22).
    EscDescription drive = drive_description();
    for (auto& sync_manager : drive.process_data.sync_managers) {
        sync_manager.control_byte = sync_manager.index == 2 ? 0x26 : 0x22;
    }
    Line line({drive});
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0600, fmmu(0x1000, 6, 0x1100, false));
    line.fpwr(kFirstStation, 0x0610, fmmu(0x1006, 8, 0x1180, true));
    line.fpwr(kFirstStation, 0x0800,
              bytes({0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80, 0x00, 0x22, 0x00, 0x01, 0x00}));
    line.fpwr(kFirstStation, 0x0120, le16(0x0002));
    line.fpwr(kFirstStation, 0x0810, bytes({0x00, 0x11, 0x06, 0x00, 0x26, 0x00, 0x01, 0x00}));
    line.fpwr(kFirstStation, 0x0818, bytes({0x80, 0x11, 0x08, 0x00, 0x22, 0x00, 0x01, 0x00}));
    line.fpwr(kFirstStation, 0x0120, le16(0x0004));
    line.fpwr(kFirstStation, 0x0120, le16(0x0008));
    REQUIRE(line.fprd(kFirstStation, 0x0130, 1)[0] == 0x08);

    std::optional<std::uint16_t> last_counter;
    for (int cycle = 0; cycle < 5; ++cycle) {
        INFO("cycle " << cycle);
        const auto outputs = bytes({cycle, cycle + 1, cycle + 2, cycle + 3, cycle + 4, cycle + 5});
        const Datagram written = line.transact(logical(Command::Lwr, 0x1000, outputs));
        CHECK(written.wkc == 1);
        const Datagram read = line.transact(logical(Command::Lrd, 0x1006, std::vector<std::uint8_t>(8, 0)));
        CHECK(read.wkc == 1);
        const std::vector<std::uint8_t> inputs(read.data.begin(), read.data.end());
        if (last_counter) CHECK(counter_of(inputs) != *last_counter);
        last_counter = counter_of(inputs);
    }
}
