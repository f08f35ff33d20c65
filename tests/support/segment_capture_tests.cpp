// The capture reader the failover tests and the benchmarks judge by: which
// master's process data reached the slaves, read from a pcap written here
// frame by frame, so the attribution rules are checked without a pair.

#include <pcap/pcap.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"
#include "segment_capture.hpp"
#include "temp_dir.hpp"

using namespace ecpair;
using ecpair::test::read_segment_capture;

namespace {

constexpr std::uint32_t kMasterA = 0xaaaa01;  // NIC bytes of master A's MAIN adapter
constexpr std::uint32_t kMasterARed = 0xaaaa02;
constexpr std::uint32_t kMasterB = 0xbbbb01;
constexpr std::uint32_t kMasterBRed = 0xbbbb02;

struct Copy {
    double time_us;
    std::uint32_t nic;
    bool red;
    std::uint8_t frame_id;
};

// A frame with one LRW datagram, from the adapter with these NIC bytes.
std::vector<std::uint8_t> lrw_frame(const Copy& c) {
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
    const std::uint8_t byte0 = 0x02 | (c.red ? wire::SourceMac::kRedundancyBit : 0);
    ethernet.source = wire::MacAddress{{byte0, c.frame_id, 0x00, static_cast<std::uint8_t>(c.nic >> 16),
                                        static_cast<std::uint8_t>(c.nic >> 8), static_cast<std::uint8_t>(c.nic)}};
    std::vector<std::uint8_t> buffer(128);
    wire::FrameBuilder builder(buffer, ethernet);
    wire::DatagramHeader lrw;
    lrw.command = wire::Command::Lrw;
    lrw.address = 0x10000;
    REQUIRE(builder.append(lrw, 8));
    const auto frame = builder.finish();
    return {frame.begin(), frame.end()};
}

std::string write_capture(const std::filesystem::path& file, const std::vector<Copy>& copies) {
    pcap_t* dead = pcap_open_dead(DLT_EN10MB, 65535);
    pcap_dumper_t* dumper = pcap_dump_open(dead, file.c_str());
    REQUIRE(dumper != nullptr);
    for (const auto& c : copies) {
        const auto frame = lrw_frame(c);
        pcap_pkthdr header{};
        header.ts.tv_sec = static_cast<long>(c.time_us / 1e6);
        header.ts.tv_usec = static_cast<long>(c.time_us) % 1'000'000;
        header.caplen = header.len = static_cast<bpf_u_int32>(frame.size());
        pcap_dump(reinterpret_cast<u_char*>(dumper), &header, frame.data());
    }
    pcap_dump_close(dumper);
    pcap_close(dead);
    return file.string();
}

// One cycle of `master`: its MAIN copy and its RED copy (the RED one a bit later).
void cycle(std::vector<Copy>& out, double t, std::uint32_t main, std::uint32_t red, std::uint8_t id) {
    out.push_back({t, main, false, id});
    out.push_back({t + 20, red, true, id});
}

}  // namespace

TEST_CASE("a master's RED copy is its own delivery when the MAIN copy was lost, despite frame ids two masters shared",
          "[capture]") {
    test::TempDir dir{"ecpair-capture"};
    std::vector<Copy> copies;
    double t = 1'000'000;
    std::uint8_t id = 0;
    // B drives the slaves for 100 cycles; one of its MAIN copies is lost, so
    // that cycle's RED copy is the delivery.
    for (int i = 0; i < 100; ++i, t += 1000) {
        if (i == 50) {
            copies.push_back({t + 20, kMasterBRed, true, id++});
        } else {
            cycle(copies, t, kMasterB, kMasterBRed, id++);
        }
    }
    // Then both masters send for 5 cycles (a double line break): A's MAIN copy
    // and B's RED copy carry the same frame id a few µs apart.
    for (int i = 0; i < 5; ++i, t += 1000) {
        copies.push_back({t, kMasterA, false, id});
        copies.push_back({t + 5, kMasterBRed, true, id++});
    }
    const auto capture = read_segment_capture(write_capture(dir / "segment.pcap", copies));
    REQUIRE(capture);
    REQUIRE(capture->process_data.size() == 105);
    std::size_t from_a = 0;
    for (const auto& d : capture->process_data) from_a += d.master == kMasterA ? 1 : 0;
    CHECK(from_a == 5);  // only the five of the two-master period
    CHECK(capture->process_data[50].master == kMasterB);  // the lone RED copy stays B's
    CHECK(capture->handovers().size() == 1);              // B -> A, nothing before
}

TEST_CASE("a handover is the change of the master whose process data reaches the slaves, with the gap before it",
          "[capture]") {
    test::TempDir dir{"ecpair-capture"};
    std::vector<Copy> copies;
    double t = 1'000'000;
    std::uint8_t id = 0;
    for (int i = 0; i < 50; ++i, t += 1000) cycle(copies, t, kMasterA, kMasterARed, id++);
    t += 9000;  // ten cycles without process data: A died, B takes over
    for (int i = 0; i < 50; ++i, t += 1000) cycle(copies, t, kMasterB, kMasterBRed, id++);
    const auto capture = read_segment_capture(write_capture(dir / "segment.pcap", copies));
    REQUIRE(capture);
    const auto handovers = capture->handovers();
    REQUIRE(handovers.size() == 1);
    CHECK(handovers[0].from == kMasterA);
    CHECK(handovers[0].to == kMasterB);
    CHECK(handovers[0].gap_us == Approx(10'000));
    CHECK(capture->longest_gap_us() == Approx(10'000));
}

TEST_CASE("an unreadable capture is an error naming the file", "[capture]") {
    const auto capture = read_segment_capture("/nonexistent/segment.pcap");
    REQUIRE_FALSE(capture);
    CHECK_THAT(capture.error(), Catch::Contains("/nonexistent/segment.pcap"));
}
