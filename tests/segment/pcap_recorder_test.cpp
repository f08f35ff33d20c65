// PcapRecorder writes frames that libpcap reads back unchanged.

#include <catch2/catch.hpp>
#include <pcap/pcap.h>
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "temp_dir.hpp"
#include "ecpair/sim/pcap_recorder.hpp"

using namespace ecpair;

namespace {

using ecpair::test::TempDir;

std::vector<std::vector<std::uint8_t>> read_pcap(const std::filesystem::path& file, int& link_type) {
    char error[PCAP_ERRBUF_SIZE];
    pcap_t* pcap = pcap_open_offline(file.c_str(), error);
    REQUIRE(pcap != nullptr);
    link_type = pcap_datalink(pcap);
    std::vector<std::vector<std::uint8_t>> frames;
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(pcap, &header, &data) == 1) frames.emplace_back(data, data + header->caplen);
    pcap_close(pcap);
    return frames;
}

}  // namespace

TEST_CASE("recorded frames read back in order, after flush and after close", "[pcap]") {
    TempDir dir("ecsim-pcap-test");
    const auto file = dir.path() / "frames.pcap";
    std::vector<std::uint8_t> first(60, 0x11);
    std::vector<std::uint8_t> second(1514, 0x22);
    second[0] = 0x01;

    auto recorder = sim::PcapRecorder::create(file.string());
    REQUIRE(recorder);
    CHECK_FALSE(recorder->has_unflushed());
    recorder->record(first, std::chrono::system_clock::now());
    CHECK(recorder->has_unflushed());
    recorder->flush();
    CHECK_FALSE(recorder->has_unflushed());

    int link_type = 0;
    auto frames = read_pcap(file, link_type);
    CHECK(link_type == DLT_EN10MB);
    REQUIRE(frames.size() == 1);
    CHECK(frames[0] == first);

    recorder->record(second, std::chrono::system_clock::now());
    {
        auto closing = std::move(recorder).value();  // the destructor flushes
    }
    frames = read_pcap(file, link_type);
    REQUIRE(frames.size() == 2);
    CHECK(frames[1] == second);
}

TEST_CASE("an unwritable pcap path is an error naming the file", "[pcap]") {
    const auto recorder = sim::PcapRecorder::create("/nonexistent-dir/ecsim.pcap");
    REQUIRE_FALSE(recorder);
    CHECK_THAT(recorder.error().message, Catch::StartsWith("/nonexistent-dir/ecsim.pcap: cannot open for writing"));
}
