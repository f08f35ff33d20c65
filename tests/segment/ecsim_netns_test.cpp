// The real ecsim binary on veth cables (label netns, needs root): in a
// fresh network namespace, ecsim's MAIN and RED interfaces are cabled to
// probe interfaces in the same namespace. The test sends frames from the
// probes with PcapLink, scripts faults with `ecsim ctl`, pulls the MAIN
// cable with `ip link set down`, and reads the pcap file ecsim wrote.

#include <catch2/catch.hpp>
#include <pcap/pcap.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "ecsim_bench.hpp"
#include "test_frames.hpp"

using namespace ecpair;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

std::size_t frames_in_pcap(const std::filesystem::path& file) {
    char error[PCAP_ERRBUF_SIZE];
    pcap_t* pcap = pcap_open_offline(file.c_str(), error);
    INFO(error);
    REQUIRE(pcap != nullptr);
    std::size_t count = 0;
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(pcap, &header, &data) == 1) ++count;
    pcap_close(pcap);
    return count;
}

}  // namespace

TEST_CASE("ecsim carries frames around its ring and out of the other side", "[netns][ecsim]") {
    EcsimBench bench;
    const TestFrame ring = bench.round_trip(/*from_main=*/true, /*expected_main=*/false);
    CHECK(wkc_of(ring) == 5);
    CHECK(ring.size == 60);
    const TestFrame reverse = bench.round_trip(false, true);
    CHECK(wkc_of(reverse) == 0);

    CHECK(bench.ecsim().stop() == 0);
    CHECK_THAT(bench.ecsim().log(), Catch::Contains("ecsim ready"));
}

TEST_CASE("faults scripted with ecsim ctl", "[netns][ecsim]") {
    EcsimBench bench;
    CHECK(bench.ctl("break 2") == std::make_pair(0, std::string("ok link after slave 2 broken")));
    CHECK(wkc_of(bench.round_trip(true, true)) == 2);
    const TestFrame red_half = bench.round_trip(false, false);
    CHECK(wkc_of(red_half) == 3);
    CHECK(header_of(red_half).circulating);

    CHECK(bench.ctl("repair 2").first == 0);
    CHECK(wkc_of(bench.round_trip(true, false)) == 5);

    CHECK(bench.ctl("power-off 3") == std::make_pair(0, std::string("ok slave 3 powered off")));
    CHECK(wkc_of(bench.round_trip(true, true)) == 2);
    CHECK(wkc_of(bench.round_trip(false, false)) == 2);
    CHECK(bench.ctl("power-on 3").first == 0);
    CHECK(wkc_of(bench.round_trip(true, false)) == 5);

    CHECK(bench.ctl("power-off 9") == std::make_pair(1, std::string("error: position 9 is out of range 1..5")));
    CHECK(bench.ctl("frobnicate") ==
          std::make_pair(1, std::string("error: unknown command 'frobnicate' (try 'help')")));
}

TEST_CASE("ecsim sees the MAIN cable pulled and the ring closes at slave 1", "[netns][ecsim]") {
    EcsimBench bench;
    bench.ns().set_link("probe-main", false);
    bench.await_status("main=down");
    CHECK_THAT(bench.ctl("status").second, Catch::Contains("| 1 name=") && Catch::Contains("ports=0:down/closed"));

    const TestFrame back = bench.round_trip(false, false);
    CHECK(wkc_of(back) == 5);
    CHECK(header_of(back).circulating);

    bench.ns().set_link("probe-main", true);
    bench.await_status("main=up");
    CHECK(wkc_of(bench.round_trip(true, false)) == 5);
}

namespace {

// The probe's carrier, as the kernel reports it, reaching `up` within the hang guard.
bool carrier_becomes(link::PcapLink& probe, bool up) {
    const auto give_up = std::chrono::steady_clock::now() + kHangGuard;
    while (probe.link_up() != up) {
        if (std::chrono::steady_clock::now() > give_up) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
}

}  // namespace

TEST_CASE("ecsim's interfaces are PHYs: the slave facing an interface without power, or its cable cut, takes "
          "the interface's carrier, and gives it back",
          "[netns][ecsim]") {
    EcsimBench bench;
    REQUIRE(carrier_becomes(bench.probe(true), true));
    REQUIRE(carrier_becomes(bench.probe(false), true));

    // Slave 1 faces MAIN.
    CHECK(bench.ctl("power-off 1").first == 0);
    CHECK(carrier_becomes(bench.probe(true), false));
    CHECK(bench.probe(false).link_up());
    const TestFrame rest = bench.round_trip(false, false);  // slaves 2..5 answer from RED
    CHECK(wkc_of(rest) == 4);
    CHECK(bench.ctl("power-on 1").first == 0);
    CHECK(carrier_becomes(bench.probe(true), true));
    bench.await_status("main=up");
    CHECK(wkc_of(bench.round_trip(true, false)) == 5);

    // Slave 5 faces RED.
    CHECK(bench.ctl("power-off 5").first == 0);
    CHECK(carrier_becomes(bench.probe(false), false));
    CHECK(bench.probe(true).link_up());
    CHECK(bench.ctl("power-on 5").first == 0);
    CHECK(carrier_becomes(bench.probe(false), true));

    // The MAIN cable cut inside the segment, and mended.
    CHECK(bench.ctl("break 0").first == 0);
    CHECK(carrier_becomes(bench.probe(true), false));
    CHECK(bench.ctl("repair 0").first == 0);
    CHECK(carrier_becomes(bench.probe(true), true));
    CHECK_THAT(bench.ecsim().log(), Catch::Contains("faces no PHY") && Catch::Contains("PHY is back"));
}

TEST_CASE("ecsim --pcap records every frame in and out and flushes it at exit", "[netns][ecsim]") {
    EcsimBench bench;
    for (int i = 0; i < 3; ++i) CHECK(wkc_of(bench.round_trip(true, false)) == 5);
    CHECK(bench.ecsim().stop() == 0);
    REQUIRE(std::filesystem::exists(bench.pcap()));
    CHECK(frames_in_pcap(bench.pcap()) == 2 * bench.frames_sent());
}
