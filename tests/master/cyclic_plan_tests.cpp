// The cyclic plan from hand-made ENI models: both offset conventions, LRW
// refused or split with WKCs from FMMU directions (never an expected WKC the
// ENI does not give), frame packing, and the state from which a datagram's
// WKC is checked; the last two also with the shared ENIs of issue 29
// (tests/data/eni_extra/).

#include <filesystem>

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/cyclic_exchange.hpp"
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

// A slave whose InitCmd (PS unless said) writes one FMMU record, mapping process RAM at `physical`.
eni::Slave slave_with_fmmu(std::uint32_t logical, std::uint16_t length, bool read, bool write,
                           std::uint16_t physical = 0x1100, eni::Transition transition = eni::Transition::PS) {
    eni::Slave s;
    eni::EcatCmd c;
    c.command = wire::Command::Fpwr;
    c.ado = wire::reg::kFmmuBase;
    c.transitions.add(transition);
    wire::FmmuConfig f;
    f.logical_start = logical;
    f.length = length;
    f.physical_start = physical;
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
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 42, 7, 0, 0)});
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
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 1000, std::nullopt, 0, 0),
                         cmd(wire::Command::Lrw, 0x10001000, 1000, std::nullopt, 1000, 1000)});
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

TEST_CASE("a split LRW whose FMMUs do not give the ENI's WKC is refused, never expected to count 0", "[plan]") {
    // The ENI says 3 (one slave in and out); no FMMU record maps the range (an encrypted or edited file).
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 4, 3, 0, 0, 77)});
    eni.slaves.push_back(slave_with_fmmu(0x20000000, 4, true, true));
    auto plan = CyclicPlan::build(eni, {true, true});
    REQUIRE_FALSE(plan);
    INFO(plan.error().message);
    CHECK(plan.error().message.find("LRW at line 77 expects WKC 3") != std::string::npos);
    CHECK(plan.error().message.find("0 writer(s) and 0 reader(s) (WKC 0)") != std::string::npos);

    // Without cable redundancy the LRW goes out as it is, checked against the ENI's 3.
    auto plain = CyclicPlan::build(eni, {});
    REQUIRE(plain);
    CHECK(plain->frames[0].datagrams[0].expected_wkc == std::optional<std::uint16_t>(3));
}

TEST_CASE("a split LRW without Cnt leaves both halves unchecked", "[plan]") {
    auto eni = eni_with({cmd(wire::Command::Lrw, 0x10000000, 4, std::nullopt, 0, 0)});
    eni.slaves.push_back(slave_with_fmmu(0x10000000, 4, true, true));
    auto plan = CyclicPlan::build(eni, {true, true});
    REQUIRE(plan);
    const auto& d = plan->frames[0].datagrams;
    REQUIRE(d.size() == 2);
    CHECK_FALSE(d[0].expected_wkc);
    CHECK_FALSE(d[1].expected_wkc);
}

TEST_CASE("process data is checked from SAFEOP, a register range from the state its FMMU is set in", "[plan]") {
    auto eni =
        eni_with({cmd(wire::Command::Lrd, 0x10000000, 4, 1, 0, 0), cmd(wire::Command::Lwr, 0x10001000, 4, 1, 4, 4),
                  cmd(wire::Command::Lrd, 0x09000000, 1, 1, 8, 8), cmd(wire::Command::Lrd, 0x30000000, 2, 1, 9, 9),
                  brd_al_status(2, 11, 11)});
    // Process data FMMUs set in IP (written early) still count from SAFEOP: the slave exchanges none in PREOP.
    eni.slaves.push_back(slave_with_fmmu(0x10000000, 4, true, false, 0x1400, eni::Transition::IP));
    eni.slaves.push_back(slave_with_fmmu(0x10001000, 4, false, true, 0x1100, eni::Transition::PS));
    // The mailbox-state FMMU maps SM1's status register, set in IP: valid in PREOP.
    eni.slaves.push_back(slave_with_fmmu(0x09000000, 1, true, false, 0x080D, eni::Transition::IP));
    auto plan = CyclicPlan::build(eni, {});
    REQUIRE(plan);
    const auto& d = plan->frames[0].datagrams;
    REQUIRE(d.size() == 5);
    CHECK(d[0].valid_from == eni::SlaveState::Safeop);
    CHECK(d[1].valid_from == eni::SlaveState::Safeop);
    CHECK(d[2].valid_from == eni::SlaveState::Preop);
    CHECK(d[3].valid_from == eni::SlaveState::Safeop);  // mapped by nobody: no process data before SAFEOP either
    CHECK(d[4].valid_from == eni::SlaveState::Preop);   // the AL-status BRD

    // In PREOP a reply where no slave counted the process data is no WKC error; in SAFEOP it is.
    CyclicExchange exchange(std::move(plan).value());
    std::vector<std::uint8_t> outputs(16, 0), inputs(16, 0), buffer(wire::kMaxFrameSize);
    std::vector<WkcMismatch> mismatches;
    mismatches.reserve(8);
    wire::EthernetHeader eth;
    for (const auto state : {eni::SlaveState::Preop, eni::SlaveState::Safeop}) {
        INFO("state " << eni::to_string(state));
        const auto frame = exchange.build(0, state, outputs, eth, buffer);
        auto view = wire::FrameView::parse(frame);
        REQUIRE(view);
        for (auto datagram : *view) {
            // Only the AL-status BRD and the mailbox-state LRD answer, as slaves in PREOP do.
            const bool answers = datagram.command() == wire::Command::Brd || datagram.address() == 0x09000000;
            datagram.set_wkc(answers ? (datagram.command() == wire::Command::Brd ? 2 : 1) : 0);
        }
        mismatches.clear();
        const auto result = exchange.complete(0, *wire::ConstFrameView::parse(frame), inputs, mismatches);
        CHECK(result.layout_ok);
        CHECK(result.wkc_errors == (state == eni::SlaveState::Preop ? 0 : 3));
        CHECK(exchange.counters_complete(0, *wire::ConstFrameView::parse(frame)) == (state == eni::SlaveState::Preop));
    }
}

namespace {

std::shared_ptr<const eni::EniConfig> extra_eni(const std::string& name) {
    auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_extra/") + name);
    INFO(name << ": " << (loaded ? std::string("loaded") : loaded.error().describe()));
    REQUIRE(loaded);
    return *loaded;
}

}  // namespace

TEST_CASE("an ENI listing its process data in PREOP too (Panasonic): no WKC error before SAFEOP", "[plan]") {
    const auto eni = extra_eni("preop_process_data_2slaves.xml");
    auto plan = CyclicPlan::build(*eni, {});
    REQUIRE(plan);
    REQUIRE(plan->frames.size() == 1);
    const auto& d = plan->frames[0].datagrams;
    REQUIRE(d.size() == 3);
    for (const auto& datagram : d) {
        INFO(datagram.comment);
        CHECK(datagram.states.contains(eni::SlaveState::Preop));  // sent in PREOP, as the ENI says
        CHECK(datagram.valid_from ==
              (datagram.command == wire::Command::Brd ? eni::SlaveState::Preop : eni::SlaveState::Safeop));
    }

    // In PREOP the slaves count the AL-status BRD only; from SAFEOP a missing count is an error.
    CyclicExchange exchange(std::move(plan).value());
    std::vector<std::uint8_t> outputs(64, 0), inputs(64, 0), buffer(wire::kMaxFrameSize);
    std::vector<WkcMismatch> mismatches;
    mismatches.reserve(8);
    wire::EthernetHeader eth;
    for (const auto state : {eni::SlaveState::Preop, eni::SlaveState::Safeop, eni::SlaveState::Op}) {
        INFO("state " << eni::to_string(state));
        const auto frame = exchange.build(0, state, outputs, eth, buffer);
        auto view = wire::FrameView::parse(frame);
        REQUIRE(view);
        for (auto datagram : *view) datagram.set_wkc(datagram.command() == wire::Command::Brd ? 2 : 0);
        mismatches.clear();
        const auto result = exchange.complete(0, *wire::ConstFrameView::parse(frame), inputs, mismatches);
        CHECK(result.layout_ok);
        CHECK(result.wkc_errors == (state == eni::SlaveState::Preop ? 0 : 2));
    }
}

TEST_CASE("an LRW whose Cnt its FMMU records do not give loads, and is refused when it must be split", "[plan]") {
    const auto eni = extra_eni("lrw_unmapped_fmmu_2slaves.xml");
    // Sent as it is, the LRW is checked against the ENI's Cnt.
    auto plain = CyclicPlan::build(*eni, {});
    REQUIRE(plain);
    REQUIRE_FALSE(plain->frames.empty());
    CHECK(plain->frames[0].datagrams[0].command == wire::Command::Lrw);
    CHECK(plain->frames[0].datagrams[0].expected_wkc == std::optional<std::uint16_t>(6));

    // Split for cable redundancy, nothing derives the 6: refused, naming the file, the line and what to do.
    auto split = CyclicPlan::build(*eni, {true, true});
    REQUIRE_FALSE(split);
    INFO(split.error().message);
    CHECK(split.error().message.find("lrw_unmapped_fmmu_2slaves.xml: the LRW at line") != std::string::npos);
    CHECK(split.error().message.find("expects WKC 6") != std::string::npos);
    CHECK(split.error().message.find("0 writer(s) and 0 reader(s) (WKC 0)") != std::string::npos);
    CHECK(split.error().message.find("export it again") != std::string::npos);
}

TEST_CASE("the real ENIs' LRWs split with the WKCs their FMMU records give, the encrypted one is refused", "[plan]") {
    // The demo runs twincat_kpierczy_5slaves.xml with split_lrw: a refused split would stop the daemon.
    std::size_t with_lrw = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(ECPAIR_TEST_DATA_DIR "/eni"))) {
        if (entry.path().extension() != ".xml") continue;
        INFO(entry.path().filename().string());
        auto loaded = eni::load_eni_file(entry.path().string());
        if (!loaded) continue;  // the real files' own tests say which load
        if (!(*loaded)->uses_logical_read_write()) continue;
        ++with_lrw;
        auto plan = CyclicPlan::build(**loaded, {true, true});
        INFO((plan ? std::string("split") : plan.error().message));
        // The Murrelektronik file's process-data FMMU records are encrypted (its SOURCES.md entry): none
        // maps the LRW's range, and the split is refused rather than run expecting WKC 0.
        if (entry.path().filename() == "ecengineer_murrelektronik_encrypted_2slaves.xml") {
            REQUIRE_FALSE(plan);
            CHECK(plan.error().message.find("expects WKC 3") != std::string::npos);
        } else {
            CHECK(plan);
        }
    }
    CHECK(with_lrw > 1);
}
