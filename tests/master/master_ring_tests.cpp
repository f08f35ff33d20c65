// The Master with its real threads (cycle and receive threads) against an
// in-process simulated ring (MemoryLinks + ecsim's Segment): an acyclic
// exchange goes through the cycle. Cable redundancy cycle by cycle is in
// cable_redundancy_tests.cpp.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/cycle_thread.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/master/receive_thread.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "simulated_ring.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

std::shared_ptr<const eni::EniConfig> generated(std::uint32_t slaves) {
    sim::GeneratedEniOptions options;
    options.slaves = slaves;
    options.input_bytes = 8;
    options.output_bytes = 6;
    auto eni = eni::load_eni_string(sim::generate_eni(options), "generated.xml");
    REQUIRE(eni);
    return *eni;
}

}  // namespace

TEST_CASE("an acyclic BRD through the closed ring counts every slave", "[master][ring]") {
    const auto eni = generated(5);
    test::SimulatedRing ring(*eni);
    master::EventQueue events;
    master::MasterOptions options;
    options.cable_redundancy = true;
    auto created = master::Master::create(eni, options, ring.main(), &ring.red(), events);
    REQUIRE(created);
    auto& m = **created;
    master::CycleThread cycle({1ms, 0, 0ns, "test-cycle"}, [&](link::Clock::time_point t) { m.run_cycle(t); });
    master::ReceiveThread rx_main(ring.main(), [&](ConstBytes f, link::Clock::time_point t) { m.on_frame(master::LinkRole::Main, f, t); }, "rx-main");
    master::ReceiveThread rx_red(ring.red(), [&](ConstBytes f, link::Clock::time_point t) { m.on_frame(master::LinkRole::Red, f, t); }, "rx-red");
    rx_main.start();
    rx_red.start();
    cycle.start();

    bus::DatagramRequest brd;
    brd.command = wire::Command::Brd;
    brd.data.assign(2, 0);
    auto reply = m.bus().exchange(brd);
    REQUIRE(reply);
    CHECK(reply->wkc == 5);
    cycle.stop();
    rx_main.stop();
    rx_red.stop();
}
