// End to end over real interfaces: ecsim on a veth cable in a namespace of
// its own, scanned from the other end of the cable by `ecpairctl scan`, for
// every shared ENI; then tshark dissects the capture ecsim recorded and must
// find no malformed frame (esc-facts.md §4).

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecsim_process.hpp"
#include "netns.hpp"
#include "temp_dir.hpp"
#include "tshark.hpp"

using namespace ecpair::test;

namespace {

struct Scan {
    int exit_status;
    std::string output;
};

Scan scan(const TestNamespace& ns, const TempDir& dir, const std::string& eni) {
    ChildProcess ctl({ecpairctl_binary(), "scan", "--if", "probe0", "--eni", eni}, dir / "scan.log", &ns);
    const auto status = ctl.wait_for_exit(std::chrono::seconds(30));
    return {status.value_or(-1), ctl.log()};
}

std::size_t count(const std::string& text, const std::string& word) {
    std::size_t n = 0;
    for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
    return n;
}

}  // namespace

TEST_CASE("ecpairctl scan finds every slave of every shared ENI on ecsim, tshark finds no malformed frame",
          "[netns][scan][tshark]") {
    // Every shared file with slaves, and the number of slaves it configures.
    const std::pair<const char*, int> files[] = {
        {"advantech_amax4270_1slave.xml", 1},
        {"advantech_io_ring_4slaves.xml", 4},
        {"ecengineer_murrelektronik_encrypted_2slaves.xml", 2},
        {"ecengineer_rocos_elmo_1slave.xml", 1},
        {"ecengineer_rocos_elmo_3slaves_bcr.xml", 3},
        {"ecengineer_rocos_elmo_4slaves.xml", 4},
        {"ecengineer_rocos_elmo_7slaves.xml", 7},
        {"ecengineer_rocos_rdm_6slaves.xml", 6},
        {"elmo_eas_rocos_1slave.xml", 1},
        {"twincat_cherryecat_cia402_1slave.xml", 1},
        {"twincat_kpierczy_5slaves.xml", 5},
    };
    for (const auto& [file, slaves] : files) {
        DYNAMIC_SECTION(file) {
            TempDir dir("ecpair-scan");
            TestNamespace ns("ecpt-scan");
            ns.create_veth("sim-main", "probe0");
            const std::string eni = fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, file);
            EcsimProcess ecsim(ns, {eni, "sim-main", std::nullopt, dir.path()});

            const auto result = scan(ns, dir, eni);
            INFO(result.output);
            CHECK(result.exit_status == 0);
            CHECK(result.output.find(std::to_string(slaves) + " slave(s) on the bus") != std::string::npos);
            CHECK(count(result.output, "  match '") == static_cast<std::size_t>(slaves));
            CHECK(result.output.find("bus matches the ENI") != std::string::npos);

            REQUIRE(ecsim.stop() == 0);
            CHECK(count_ethercat_frames(ecsim.pcap()) > static_cast<std::size_t>(10 * slaves));
            CHECK(count_malformed_ethercat_frames(ecsim.pcap()) == 0);
        }
    }
}

TEST_CASE("ecpairctl scan names an unknown slave and a missing one", "[netns][scan]") {
    TempDir dir("ecpair-scan");
    TestNamespace ns("ecpt-scan");
    ns.create_veth("sim-main", "probe0");
    const std::string eni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");
    EcsimProcess ecsim(ns, {eni, "sim-main", std::nullopt, dir.path()});

    REQUIRE(ecsim.ctl("insert-unknown 2").first == 0);
    auto result = scan(ns, dir, eni);
    INFO(result.output);
    CHECK(result.exit_status == 1);
    CHECK(result.output.find("6 slave(s) on the bus") != std::string::npos);
    CHECK(result.output.find("bus does NOT match the ENI") != std::string::npos);
    CHECK(result.output.find("position 1") != std::string::npos);
    CHECK(result.output.find("vendor 0x0badc0de") != std::string::npos);

    REQUIRE(ecsim.ctl("remove-unknown 2").first == 0);
    REQUIRE(ecsim.ctl("power-off 5").first == 0);
    result = scan(ns, dir, eni);
    INFO(result.output);
    CHECK(result.exit_status == 1);
    CHECK(result.output.find("4 slave(s) on the bus") != std::string::npos);
    CHECK(result.output.find("position 4") != std::string::npos);
    CHECK(result.output.find("found nothing") != std::string::npos);
}

TEST_CASE("ecpairctl scan on a missing interface fails with the interface named", "[netns][scan]") {
    TempDir dir("ecpair-scan");
    TestNamespace ns("ecpt-scan");
    ChildProcess ctl({ecpairctl_binary(), "scan", "--if", "nosuch0"}, dir / "scan.log", &ns);
    CHECK(ctl.wait_for_exit(std::chrono::seconds(10)) == 3);
    CHECK(ctl.log().find("nosuch0") != std::string::npos);
}
