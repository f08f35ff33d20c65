#pragma once
// ecsim on veth cables for the netns tests of the ecsim program
// (ecsim_netns_tests, ecsim_dc_netns_tests): the real binary in a fresh
// network namespace on the 5-slave TwinCAT ENI, its MAIN and RED interfaces
// cabled to probe interfaces in the same namespace, `ecsim ctl` to script it.

#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "temp_dir.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "netns.hpp"
#include "test_frames.hpp"

namespace ecpair::test {

inline const std::string kEcsim = ECSIM_BINARY;
// How long the test waits for ecsim before calling it a hang.
inline constexpr std::chrono::seconds kHangGuard{10};

// ecsim running in a namespace with two probe cables, and the probes' links.
class EcsimBench {
public:
    EcsimBench() : ns_("ecsim") {
        ns_.create_veth("sim-main", "probe-main");
        ns_.create_veth("sim-red", "probe-red");
        ecsim_.emplace(std::vector<std::string>{kEcsim, "--eni",
                                                std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml"),
                                                "--main-if", "sim-main", "--red-if", "sim-red", "--control",
                                                control().string(), "--pcap", pcap().string(), "--log-level", "debug"},
                       dir_.path() / "ecsim.log", &ns_);
        // Ready once the control socket exists (it is created last).
        const auto give_up = std::chrono::steady_clock::now() + kHangGuard;
        while (!std::filesystem::exists(control())) {
            INFO(ecsim_->log());
            REQUIRE(ecsim_->running());
            REQUIRE(std::chrono::steady_clock::now() < give_up);
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        link::PcapLinkOptions options;
        options.bpf_filter = "ether proto 0x88a4";
        NamespaceScope inside(ns_);
        auto main_probe = link::PcapLink::open("probe-main", options);
        auto red_probe = link::PcapLink::open("probe-red", options);
        REQUIRE(main_probe);
        REQUIRE(red_probe);
        main_probe_ = std::move(main_probe).value();
        red_probe_ = std::move(red_probe).value();
    }

    std::filesystem::path control() const { return dir_.path() / "ecsim.sock"; }
    std::filesystem::path pcap() const { return dir_.path() / "ecsim.pcap"; }
    const TestNamespace& ns() const { return ns_; }
    ChildProcess& ecsim() { return *ecsim_; }
    link::PcapLink& probe(bool main_side) { return main_side ? *main_probe_ : *red_probe_; }

    // `ecsim ctl --control ... <request>`: its exit status and output line.
    std::pair<int, std::string> ctl(const std::string& request) {
        std::vector<std::string> argv{kEcsim, "ctl", "--control", control().string()};
        std::istringstream words(request);
        for (std::string word; words >> word;) argv.push_back(word);
        ChildProcess client(argv, dir_.path() / "ctl.log");
        const auto status = client.wait_for_exit(kHangGuard);
        REQUIRE(status);
        std::string output = client.log();
        if (!output.empty() && output.back() == '\n') output.pop_back();
        return {*status, output};
    }

    void await_status(const std::string& text) {
        const auto give_up = std::chrono::steady_clock::now() + kHangGuard;
        while (ctl("status").second.find(text) == std::string::npos) {
            REQUIRE(std::chrono::steady_clock::now() < give_up);
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }

    // Sends a BRD of AL status on one probe and returns what arrives on `expected_main`'s probe.
    TestFrame round_trip(bool from_main, bool expected_main) {
        TestFrame frame = single(wire::Command::Brd, wire::DatagramHeader::physical(0, 0x0130), 2);
        const auto sent = probe(from_main).send(frame.bytes());
        INFO((sent ? std::string() : sent.error().message));
        REQUIRE(sent);
        ++frames_sent_;
        TestFrame back;
        const auto received = probe(expected_main).receive(back.buffer, kHangGuard);
        REQUIRE(received);
        INFO(ecsim_->log());
        REQUIRE(received->has_value());
        back.size = (*received)->size;
        return back;
    }

    std::size_t frames_sent() const { return frames_sent_; }

private:
    TempDir dir_{"ecsim-netns-test"};
    TestNamespace ns_;
    std::optional<ChildProcess> ecsim_;
    std::unique_ptr<link::PcapLink> main_probe_;
    std::unique_ptr<link::PcapLink> red_probe_;
    std::size_t frames_sent_ = 0;
};

}  // namespace ecpair::test
