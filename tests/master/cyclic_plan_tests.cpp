// The cyclic plan from hand-made ENI models: both offset conventions, LRW
// refused or split with WKCs from FMMU directions, frame packing.

#include <catch2/catch.hpp>

#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

using namespace ecpair;
using namespace ecpair::master;

namespace {

eni::StateSet all_states() {
    eni::StateSet s;
    s.add(eni::SlaveState::Preop);
    s.add(eni::SlaveState::Safeop);
    s.add(eni::SlaveState::Op);
    return s;
}

eni::CyclicCmd cmd(wire::Command c, std::uint32_t logical, std::uint16_t length, std::optional<std::uint16_t> wkc,
                   std::uint32_t in, std::uint32_t out, int line = 0) {
    eni::CyclicCmd x;
    x.states = all_states();
    x.command = c;
    x.logical_address = logical;
    x.data_length = length;
    x.expected_wkc = wkc;
    x.input_offset = in;
    x.output_offset = out;
    x.source_line = line;
    return x;
}

eni::CyclicCmd brd_al_status(std::uint16_t wkc, std::uint32_t in, std::uint32_t out) {
    auto x = cmd(wire::Command::Brd, 0, 2, wkc, in, out);
    x.adp = 0;
    x.ado = wire::reg::kAlStatus;
    return x;
}

// A slave whose PS InitCmds write one FMMU record.
eni::Slave slave_with_fmmu(std::uint32_t logical, std::uint16_t length, bool read, bool write) {
    eni::Slave s;
    eni::EcatCmd c;
    c.command = wire::Command::Fpwr;
    c.ado = wire::reg::kFmmuBase;
    wire::FmmuConfig f;
    f.logical_start = logical;
    f.length = length;
    f.read = read;
    f.write = write;
    f.active = true;
    c.data.assign(16, 0);
    f.encode(c.data);
    s.init_cmds.push_back(c);
    return s;
}

eni::EniConfig eni_with(std::vector<eni::CyclicCmd> cmds) {
    eni::EniConfig e;
    e.source_path = "test.xml";
    eni::Cyclic cyclic;
    eni::CyclicFrame frame;
    frame.cmds = std::move(cmds);
    cyclic.frames.push_back(frame);
    e.cyclic.push_back(cyclic);
    return e;
}

}  // namespace

TEST_CASE("compact offsets (EC-Engineer) are data offsets", "[plan]") {
    auto eni = eni_with({brd_al_status(3, 42, 42), cmd(wire::Command::Lrw, 0x10000000, 42, 9, 0, 0)});
    auto plan = CyclicPlan::build(eni, {});
    REQUIRE(plan);
    CHECK(plan->convention == OffsetConvention::Compact);
    REQUIRE(plan->frames.size() == 1);
    const auto& d = plan->frames[0].datagrams;
    REQUIRE(d.size() == 2);
    CHECK(*d[0].input_offset == 42);
    CHECK_FALSE(d[0].output_offset);  // BRD does not write
    CHECK(*d[1].input_offset == 0);
    CHECK(*d[1].output_offset == 0);
    CHECK(plan->input_image_size == 44);
    CHECK(plan->output_image_size == 42);
}

TEST_CASE("frame-image offsets (TwinCAT) point at datagram headers", "[plan]") {
    // 16 = 14 + 2, then each next header right after the previous datagram.
    auto eni = eni_with({cmd(wire::Command::Lrd, 0x01000000, 14, 1, 16, 16),
                         cmd(wire::Command::Lrw, 0x01000800, 56, 12, 16 + 12 + 14, 16 + 12 + 14),
                         brd_al_status(5, 16 + 12 + 14 + 12 + 56, 16 + 12 + 14 + 12 + 56)});
    auto plan = CyclicPlan::build(eni, {});
    REQUIRE(plan);
    CHECK(plan->convention == OffsetConvention::FrameImage);
    const auto& d = plan->frames[0].datagrams;
    CHECK(*d[0].input_offset == 26);
    CHECK_FALSE(d[0].output_offset);  // LRD does not write
    CHECK(*d[1].input_offset == 52);
    CHECK(*d[1].output_offset == 52);
    CHECK(*d[2].input_offset == 120);
}

TEST_CASE("cable redundancy refuses LRW and names the commands", "[plan]") {
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 42, 9, 0, 0, 1234)});
    auto plan = CyclicPlan::build(eni, {true, false});
    REQUIRE_FALSE(plan);
    CHECK(plan.error().message.find("LRW") != std::string::npos);
    CHECK(plan.error().message.find("line 1234") != std::string::npos);
    CHECK(plan.error().message.find("split_lrw") != std::string::npos);
}

TEST_CASE("split LRW becomes LWR + LRD with WKCs from FMMU directions", "[plan]") {
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 42, 9, 0, 0)});
    // Three slaves in the range: two with in+out, one input only; one outside it.
    eni.slaves.push_back(slave_with_fmmu(0x10000000, 10, true, true));
    eni.slaves.back().init_cmds.push_back(eni.slaves.back().init_cmds.front());
    eni.slaves.push_back(slave_with_fmmu(0x10000010, 10, true, true));
    eni.slaves.push_back(slave_with_fmmu(0x10000020, 4, true, false));
    eni.slaves.push_back(slave_with_fmmu(0x20000000, 4, true, true));

    const auto dirs = fmmu_directions(eni, 0x10000000, 42);
    CHECK(dirs.readers == 3);
    CHECK(dirs.writers == 2);

    auto plan = CyclicPlan::build(eni, {true, true});
    REQUIRE(plan);
    const auto& d = plan->frames[0].datagrams;
    REQUIRE(d.size() == 2);
    CHECK(d[0].command == wire::Command::Lwr);
    CHECK(*d[0].expected_wkc == 2);
    CHECK(*d[0].output_offset == 0);
    CHECK_FALSE(d[0].input_offset);
    CHECK(d[1].command == wire::Command::Lrd);
    CHECK(*d[1].expected_wkc == 3);
    CHECK(*d[1].input_offset == 0);
    CHECK_FALSE(d[1].output_offset);
    CHECK(d[0].address == d[1].address);
}

TEST_CASE("datagrams that outgrow a frame go to the next frame", "[plan]") {
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 1000, 3, 0, 0),
                         cmd(wire::Command::Lrw, 0x10001000, 1000, 3, 1000, 1000)});
    auto plan = CyclicPlan::build(eni, {true, true});
    REQUIRE(plan);
    // 4 datagrams of 1012 bytes: at most one per 1498-byte payload.
    CHECK(plan->frames.size() == 4);
    CHECK(plan->datagram_count() == 4);
}

TEST_CASE("no cyclic section gives an empty plan", "[plan]") {
    eni::EniConfig eni;
    auto plan = CyclicPlan::build(eni, {true, false});
    REQUIRE(plan);
    CHECK(plan->frames.empty());
}
