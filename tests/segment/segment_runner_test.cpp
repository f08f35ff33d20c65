// ecsim's event loop over in-memory wires (no root needed): frames in and
// out of both sides, faults through the control socket, a pulled MAIN cable,
// the pcap recording, and a clean stop.

#include <catch2/catch.hpp>
#include <pcap/pcap.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "ecpair/link/memory_link.hpp"
#include "segment_fixtures.hpp"
#include "segment_runner.hpp"

using namespace ecpair;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

namespace {

// How long a test waits for an answer before calling it a hang.
constexpr std::chrono::seconds kHangGuard{10};

wire::MacAddress mac(std::uint8_t last) { return wire::MacAddress{{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

class MemoryBench {
public:
    explicit MemoryBench(bool with_pcap)
        : dir_(std::filesystem::temp_directory_path() / ("ecsim-runner-test-" + std::to_string(::getpid()))),
          main_(link::MemoryWire::make_pair("probe-main", mac(1), "sim-main", mac(2))),
          red_(link::MemoryWire::make_pair("probe-red", mac(3), "sim-red", mac(4))),
          stop_fd_(::eventfd(0, EFD_CLOEXEC)) {
        std::filesystem::create_directories(dir_);
        std::optional<sim::PcapRecorder> pcap;
        if (with_pcap) {
            auto recorder = sim::PcapRecorder::create(pcap_path().string());
            REQUIRE(recorder);
            pcap.emplace(std::move(recorder).value());
        }
        ecsim::RunnerSetup setup{line_segment(5), std::move(main_.b), std::move(red_.b), {},
                                 std::move(pcap), control_path(),     stop_fd_, {}};
        setup.link_states.push_back(main_.wire->watch());
        setup.link_states.push_back(red_.wire->watch());
        // The PHY's carrier: the wire's (one flag for both ends, like a veth's carrier).
        setup.set_carrier = [this](sim::Side side, bool up) -> Expected<bool, std::string> {
            auto& cable = wire(side);
            if (!up && !cable.link_up()) return false;
            cable.set_link_up(up);
            return true;
        };
        auto runner = ecsim::SegmentRunner::create(std::move(setup));
        REQUIRE(runner);
        runner_ = std::move(runner).value();
        thread_ = std::thread([this] { exit_status_ = runner_->run(); });
    }

    ~MemoryBench() {
        stop();
        runner_.reset();
        ::close(stop_fd_);
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
    }

    int stop() {
        if (thread_.joinable()) {
            const std::uint64_t one = 1;
            REQUIRE(::write(stop_fd_, &one, sizeof(one)) == sizeof(one));
            thread_.join();
        }
        return exit_status_;
    }

    std::filesystem::path control_path() const { return dir_ / "ecsim.sock"; }
    std::filesystem::path pcap_path() const { return dir_ / "ecsim.pcap"; }
    link::MemoryLink& probe(sim::Side side) { return side == sim::Side::Main ? *main_.a : *red_.a; }
    link::MemoryWire& wire(sim::Side side) { return side == sim::Side::Main ? *main_.wire : *red_.wire; }

    // Sends a frame on one probe and waits for it on `expected`.
    TestFrame round_trip(sim::Side from, sim::Side expected, TestFrame frame) {
        REQUIRE(probe(from).send(frame.bytes()));
        TestFrame back;
        const auto received = probe(expected).receive(back.buffer, kHangGuard);
        REQUIRE(received);
        REQUIRE(received->has_value());
        back.size = (*received)->size;
        return back;
    }

    std::string request(const std::string& line) {
        const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        REQUIRE(fd >= 0);
        timeval timeout{kHangGuard.count(), 0};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        const std::string path = control_path().string();
        std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
        REQUIRE(::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0);
        const std::string sent = line + "\n";
        REQUIRE(::send(fd, sent.data(), sent.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(sent.size()));
        std::string response;
        char c = 0;
        while (::recv(fd, &c, 1, 0) == 1 && c != '\n') response += c;
        ::close(fd);
        return response;
    }

    // Asks for the status until it contains `text` (the runner applies link
    // changes asynchronously); bounded by the hang guard.
    void await_status(const std::string& text) {
        const auto give_up = std::chrono::steady_clock::now() + kHangGuard;
        while (request("status").find(text) == std::string::npos) {
            REQUIRE(std::chrono::steady_clock::now() < give_up);
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }

private:
    std::filesystem::path dir_;
    link::MemoryWire::Ends main_;
    link::MemoryWire::Ends red_;
    int stop_fd_;
    std::unique_ptr<ecsim::SegmentRunner> runner_;
    std::thread thread_;
    int exit_status_ = -1;
};

TestFrame brd() { return single(Command::Brd, DatagramHeader::physical(0, 0x0130), 2); }

}  // namespace

TEST_CASE("ecsim's loop carries frames between the sides and obeys the control socket", "[runner]") {
    MemoryBench bench(/*with_pcap=*/false);

    const TestFrame ring = bench.round_trip(sim::Side::Main, sim::Side::Red, brd());
    CHECK(wkc_of(ring) == 5);
    const TestFrame reverse = bench.round_trip(sim::Side::Red, sim::Side::Main, brd());
    CHECK(wkc_of(reverse) == 0);

    CHECK(bench.request("break 2") == "ok link after slave 2 broken");
    CHECK(wkc_of(bench.round_trip(sim::Side::Main, sim::Side::Main, brd())) == 2);
    const TestFrame red_half = bench.round_trip(sim::Side::Red, sim::Side::Red, brd());
    CHECK(wkc_of(red_half) == 3);
    CHECK(header_of(red_half).circulating);
    CHECK(bench.request("repair 2") == "ok link after slave 2 repaired");

    CHECK(bench.request("power-off 4") == "ok slave 4 powered off");
    CHECK(wkc_of(bench.round_trip(sim::Side::Main, sim::Side::Main, brd())) == 3);
    CHECK(bench.request("power-on 4") == "ok slave 4 powered on");
    CHECK(wkc_of(bench.round_trip(sim::Side::Main, sim::Side::Red, brd())) == 5);

    CHECK(bench.request("power-off 42") == "error: position 42 is out of range 1..5");
    CHECK(bench.stop() == ecsim::kExitOk);
}

TEST_CASE("ecsim follows the MAIN cable's carrier", "[runner]") {
    MemoryBench bench(/*with_pcap=*/false);
    bench.wire(sim::Side::Main).set_link_up(false);
    bench.await_status("main=down");
    CHECK_THAT(bench.request("status"), Catch::Contains("| 1 name=\"S1\"") && Catch::Contains("ports=0:down/closed"));

    const TestFrame back = bench.round_trip(sim::Side::Red, sim::Side::Red, brd());
    CHECK(wkc_of(back) == 5);
    CHECK(header_of(back).circulating);

    bench.wire(sim::Side::Main).set_link_up(true);
    bench.await_status("main=up");
    CHECK(wkc_of(bench.round_trip(sim::Side::Main, sim::Side::Red, brd())) == 5);
}

TEST_CASE("the interface facing a slave without power, or a cut cable, loses its carrier, and gets it back",
          "[runner]") {
    MemoryBench bench(/*with_pcap=*/false);
    const auto main = sim::Side::Main;
    const auto red = sim::Side::Red;

    SECTION("the slave facing MAIN powered off and on") {
        CHECK(bench.request("power-off 1") == "ok slave 1 powered off");
        CHECK_FALSE(bench.probe(main).link_up());
        CHECK(bench.probe(red).link_up());
        bench.await_status("main=down");
        // The rest of the ring answers from RED, processed from slave 2 on.
        const TestFrame back = bench.round_trip(red, red, brd());
        CHECK(wkc_of(back) == 4);
        CHECK(bench.request("power-on 1") == "ok slave 1 powered on");
        CHECK(bench.probe(main).link_up());
        bench.await_status("main=up");
        CHECK(wkc_of(bench.round_trip(main, red, brd())) == 5);
    }
    SECTION("the slave facing RED powered off and on") {
        CHECK(bench.request("power-off 5") == "ok slave 5 powered off");
        CHECK_FALSE(bench.probe(red).link_up());
        CHECK(bench.probe(main).link_up());
        CHECK(wkc_of(bench.round_trip(main, main, brd())) == 4);
        CHECK(bench.request("power-on 5") == "ok slave 5 powered on");
        CHECK(bench.probe(red).link_up());
        bench.await_status("red=up");
        CHECK(wkc_of(bench.round_trip(main, red, brd())) == 5);
    }
    SECTION("the MAIN cable cut inside the segment and mended") {
        CHECK(bench.request("break 0") == "ok link after slave 0 broken");
        CHECK_FALSE(bench.probe(main).link_up());
        CHECK(bench.request("repair 0") == "ok link after slave 0 repaired");
        CHECK(bench.probe(main).link_up());
    }
    SECTION("a slave further down changes no interface's carrier") {
        CHECK(bench.request("power-off 3") == "ok slave 3 powered off");
        CHECK(bench.probe(main).link_up());
        CHECK(bench.probe(red).link_up());
    }
    SECTION("a carrier taken away by someone else is not raised by a power-on") {
        bench.wire(main).set_link_up(false);
        bench.await_status("main=down");
        CHECK(bench.request("power-off 1") == "ok slave 1 powered off");
        CHECK(bench.request("power-on 1") == "ok slave 1 powered on");
        CHECK_FALSE(bench.probe(main).link_up());
    }
}

TEST_CASE("ecsim records every frame in and out, and flushes at exit", "[runner][pcap]") {
    MemoryBench bench(/*with_pcap=*/true);
    const TestFrame sent = brd();
    const TestFrame back = bench.round_trip(sim::Side::Main, sim::Side::Red, sent);
    CHECK(bench.stop() == ecsim::kExitOk);

    char error[PCAP_ERRBUF_SIZE];
    pcap_t* pcap = pcap_open_offline(bench.pcap_path().c_str(), error);
    REQUIRE(pcap != nullptr);
    std::vector<std::vector<std::uint8_t>> frames;
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(pcap, &header, &data) == 1) frames.emplace_back(data, data + header->caplen);
    pcap_close(pcap);

    REQUIRE(frames.size() == 2);
    CHECK(frames[0] == std::vector<std::uint8_t>(sent.bytes().begin(), sent.bytes().end()));
    CHECK(frames[1] == std::vector<std::uint8_t>(back.bytes().begin(), back.bytes().end()));
}

TEST_CASE("a cable that damages frames makes the first slave's port count them", "[runner][error-counters]") {
    MemoryBench bench(/*with_pcap=*/false);
    CHECK(bench.request("impair main 100 0 0") == "ok MAIN cable: loss 100%, duplicates 0%, delay 0 µs");
    TestFrame frame = brd();
    REQUIRE(bench.probe(sim::Side::Main).send(frame.bytes()));
    bench.await_status("damaged_dropped=1 ");
    const std::string status = bench.request("status");
    CHECK_THAT(status, Catch::Contains("out=MAIN:0,RED:0 "));
    CHECK_THAT(status, Catch::Contains("| 1 name=\"S1\"") && Catch::Contains("errors=0:1/1/0/0,1:0/0/0/0 group=0 | 2"));
    CHECK_THAT(status, Catch::Contains("errors=0:0/0/1/0,1:0/0/0/0 group=0 | 3"));

    CHECK(bench.request("impair main 0 0 0") == "ok MAIN cable: loss 0%, duplicates 0%, delay 0 µs");
    CHECK(bench.request("port-errors 2 A 1") == "ok the next 1 frame(s) arriving at slave 2 port A are damaged there");
    REQUIRE(bench.probe(sim::Side::Main).send(frame.bytes()));
    bench.await_status("damaged_dropped=2 ");
    CHECK_THAT(bench.request("status"), Catch::Contains("errors=0:1/1/1/0,1:0/0/0/0 group=0 | 3") &&
                                            Catch::Contains("errors=0:0/0/2/0,1:0/0/0/0 group=0 | 4"));
    CHECK(wkc_of(bench.round_trip(sim::Side::Main, sim::Side::Red, brd())) == 5);
    CHECK(bench.stop() == ecsim::kExitOk);
}
