// The ecsim program's command line, without network namespaces: usage
// errors (exit 2), start-up failures (exit 1) and `ecsim ctl` with nothing
// listening (exit 3), each with a message that names the problem.

#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>

#include "netns.hpp"

using namespace ecpair::test;

namespace {

const std::string kEcsim = ECSIM_BINARY;

struct Outcome {
    int status;
    std::string output;
};

Outcome run_ecsim(std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), kEcsim);
    const auto log = std::filesystem::temp_directory_path() / ("ecsim-cli-test-" + std::to_string(::getpid()) + ".log");
    ChildProcess ecsim(arguments, log);
    const auto status = ecsim.wait_for_exit(std::chrono::seconds(10));
    REQUIRE(status);
    Outcome outcome{*status, ecsim.log()};
    std::filesystem::remove(log);
    return outcome;
}

}  // namespace

TEST_CASE("ecsim refuses bad command lines with exit status 2", "[ecsim][cli]") {
    const auto missing_eni = run_ecsim({"--main-if", "eth0"});
    CHECK(missing_eni.status == 2);
    CHECK_THAT(missing_eni.output,
               Catch::StartsWith("ecsim: --eni FILE is required") && Catch::Contains("usage: ecsim"));

    const auto unknown = run_ecsim({"--eni", "x.xml", "--main-if", "eth0", "--frobnicate"});
    CHECK(unknown.status == 2);
    CHECK_THAT(unknown.output, Catch::Contains("frobnicate"));

    const auto level = run_ecsim({"--eni", "x.xml", "--main-if", "eth0", "--log-level", "loud"});
    CHECK(level.status == 2);
    CHECK_THAT(level.output, Catch::StartsWith("ecsim: --log-level: 'loud' is not one of"));

    const auto same = run_ecsim({"--eni", "x.xml", "--main-if", "eth0", "--red-if", "eth0"});
    CHECK(same.status == 2);
    CHECK_THAT(same.output, Catch::StartsWith("ecsim: --red-if must differ from --main-if"));

    const auto bad_name = run_ecsim({"--eni", "x.xml", "--main-if", "a/b"});
    CHECK(bad_name.status == 2);
    CHECK_THAT(bad_name.output, Catch::StartsWith("ecsim: --main-if: 'a/b' is not an interface name"));

    const auto drift = run_ecsim({"--eni", "x.xml", "--main-if", "eth0", "--dc-drift-ppm", "5000"});
    CHECK(drift.status == 2);
    CHECK_THAT(drift.output, Catch::StartsWith("ecsim: --dc-drift-ppm: must be 0..1000 (got 5000"));

    const auto delay = run_ecsim({"--eni", "x.xml", "--main-if", "eth0", "--dc-cable-delay-ns", "200000"});
    CHECK(delay.status == 2);
    CHECK_THAT(delay.output, Catch::StartsWith("ecsim: --dc-cable-delay-ns: must be 0..100000 ns (got 200000)"));

    const auto ctl_without_socket = run_ecsim({"ctl", "status"});
    CHECK(ctl_without_socket.status == 2);
    CHECK_THAT(ctl_without_socket.output, Catch::StartsWith("ecsim: ctl needs --control PATH"));

    const auto ctl_without_command = run_ecsim({"ctl", "--control", "/tmp/none.sock"});
    CHECK(ctl_without_command.status == 2);
}

TEST_CASE("ecsim --help prints the usage and succeeds", "[ecsim][cli]") {
    const auto help = run_ecsim({"--help"});
    CHECK(help.status == 0);
    CHECK_THAT(help.output, Catch::StartsWith("usage: ecsim --eni FILE --main-if IF") && Catch::Contains("--pcap"));
}

TEST_CASE("ecsim fails to start with exit status 1 and says why", "[ecsim][cli]") {
    const auto missing =
        run_ecsim({"--eni", "/nonexistent/eni.xml", "--main-if", "eth0", "--control", "/tmp/ecsim-cli-never.sock"});
    CHECK(missing.status == 1);
    CHECK_THAT(missing.output, Catch::Contains("/nonexistent/eni.xml"));

    const auto no_interface = run_ecsim({"--eni", std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml"),
                                         "--main-if", "ecsim-nosuch0", "--control", "/tmp/ecsim-cli-never.sock"});
    CHECK(no_interface.status == 1);
    CHECK_THAT(no_interface.output, Catch::Contains("MAIN: ") && Catch::Contains("ecsim-nosuch0"));
}

TEST_CASE("ecsim ctl with nothing listening exits with status 3", "[ecsim][cli]") {
    const auto unreachable = run_ecsim({"ctl", "--control", "/tmp/ecsim-cli-test-nobody.sock", "status"});
    CHECK(unreachable.status == 3);
    CHECK_THAT(unreachable.output, Catch::StartsWith("ecsim ctl: /tmp/ecsim-cli-test-nobody.sock: "));
}
