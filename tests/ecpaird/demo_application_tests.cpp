// The demo's loopback check: it counts a mismatch only where the slaves
// must have had this cycle's or the previous cycle's outputs, i.e. when both
// cycles came back complete, and never right after the master stood by.

#include <catch2/catch.hpp>

#include "demo_application.hpp"

using namespace ecpair;
using daemon::DemoApplication;

namespace {

// One slave with 4 output bytes at 0 and 6 input bytes at 0 (a 2-byte counter, then the echo).
eni::EniConfig one_slave() {
    eni::EniConfig eni;
    eni::Slave slave;
    slave.info.name = "Term 1";
    slave.info.phys_addr = 1001;
    slave.process_data.send = eni::BitRange{0, 32};
    slave.process_data.recv = eni::BitRange{0, 48};
    eni.slaves.push_back(slave);
    return eni;
}

// The slave's answer: the echo of `outputs` behind the counter.
void echo(master::ProcessImage& image, ConstBytes outputs) {
    std::copy(outputs.begin(), outputs.begin() + 4, image.inputs().begin() + 2);
}

master::CycleInfo cycle(std::uint64_t n, bool complete, bool sending = true) {
    return master::CycleInfo{n, eni::SlaveState::Op, complete, sending};
}

struct Loop {
    Loop() : app(eni, config::DemoKind::LoopbackCheck, 1) {}

    // One cycle in which the slave echoed what it held: `held` is the outputs it got.
    void run(std::uint64_t n, bool complete, const std::vector<std::uint8_t>& held, bool sending = true) {
        echo(image, held);
        app.on_cycle(image, cycle(n, complete, sending));
    }
    std::vector<std::uint8_t> outputs() const { return {image.outputs().begin(), image.outputs().end()}; }

    eni::EniConfig eni = one_slave();
    master::ProcessImage image{6, 4, std::nullopt};
    DemoApplication app;
};

}  // namespace

TEST_CASE("loopback check: an echo of this or the previous cycle's outputs matches, any other is a mismatch",
          "[ecpaird][demo]") {
    Loop loop;
    REQUIRE(loop.app.checked_slaves() == 1);
    for (std::uint64_t n = 1; n <= 10; ++n) loop.run(n, true, loop.outputs());  // echo of what was just sent
    CHECK(loop.app.stats().cycles_checked == 9);  // the first cycle has no previous one
    CHECK(loop.app.stats().mismatches == 0);

    std::vector<std::uint8_t> before = loop.outputs();
    loop.run(11, true, loop.outputs());
    loop.run(12, true, before);  // one cycle behind (an LRW reads before it writes): still fine
    CHECK(loop.app.stats().mismatches == 0);

    loop.run(13, true, {0xde, 0xad, 0xbe, 0xef});  // neither: the data path broke it
    CHECK(loop.app.stats().mismatches == 1);
    CHECK(loop.app.stats().slaves_checked == 12);
}

TEST_CASE("loopback check: a cycle after an incomplete one is not checked (its outputs may not have arrived)",
          "[ecpaird][demo]") {
    Loop loop;
    for (std::uint64_t n = 1; n <= 5; ++n) loop.run(n, true, loop.outputs());
    const auto checked = loop.app.stats().cycles_checked;
    const auto stale = loop.outputs();
    loop.run(6, true, loop.outputs());
    loop.run(7, false, stale);  // this cycle's output frame was lost
    loop.run(8, true, stale);   // the slave still echoes older outputs: not counted
    CHECK(loop.app.stats().cycles_checked == checked + 1);
    CHECK(loop.app.stats().mismatches == 0);
    loop.run(9, true, loop.outputs());
    CHECK(loop.app.stats().cycles_checked == checked + 2);
    CHECK(loop.app.stats().mismatches == 0);
}

TEST_CASE("loopback check: after standing by, the first cycles are not compared with outputs from before",
          "[ecpaird][demo]") {
    Loop loop;
    for (std::uint64_t n = 1; n <= 5; ++n) loop.run(n, true, loop.outputs());
    // INACTIVE for a while: the partner wrote other outputs, which the slaves hold.
    for (std::uint64_t n = 6; n <= 20; ++n) loop.run(n, true, {0x11, 0x22, 0x33, 0x44}, /*sending=*/false);
    const auto checked = loop.app.stats().cycles_checked;
    // Active again: the mirrored image's outputs were the partner's; the echo is of those.
    std::fill(loop.image.outputs().begin(), loop.image.outputs().end(), std::uint8_t{0x55});
    loop.run(21, true, {0x11, 0x22, 0x33, 0x44});
    loop.run(22, true, {0x55, 0x55, 0x55, 0x55});
    CHECK(loop.app.stats().mismatches == 0);
    CHECK(loop.app.stats().cycles_checked == checked + 1);  // only cycle 22: cycle 21 had no previous cycle
}
