// ecpair-capture-analysis: figures from packet captures (libpcap files), for
// the redundancy benchmarks.
//
//   delay IN.pcap OUT.pcap
//       Store-and-forward delay: for every frame in OUT, the frame in IN with
//       the same source MAC bytes 1-5 (frame id, NIC bytes) and length that
//       arrived last before it; prints p50/p99/max of OUT - IN in µs.
//       (Byte 0 may differ: the forwarding bits.)
//   gaps SEGMENT.pcap [CYCLE_US]
//       The timeline of takeovers from ecsim's --pcap (SegmentCapture): every
//       change of the master whose process data reached the slaves, with the
//       time the slaves went without process data (in ms and, with the cycle
//       time, in cycles), and the cycles the masters' CMFs numbered that no
//       master or two masters sent.

#include <pcap/pcap.h>

#include <algorithm>
#include <cstdlib>
#include <array>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "segment_capture.hpp"

namespace {

using namespace ecpair;

struct Frame {
    double time_us;
    std::vector<std::uint8_t> bytes;
};

std::vector<Frame> read(const std::string& file) {
    char error[PCAP_ERRBUF_SIZE];
    pcap_t* pcap = pcap_open_offline(file.c_str(), error);
    if (pcap == nullptr) {
        std::fprintf(stderr, "%s: %s\n", file.c_str(), error);
        std::exit(2);
    }
    std::vector<Frame> frames;
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(pcap, &header, &data) == 1) {
        frames.push_back({static_cast<double>(header->ts.tv_sec) * 1e6 + static_cast<double>(header->ts.tv_usec),
                          std::vector<std::uint8_t>(data, data + header->caplen)});
    }
    pcap_close(pcap);
    std::sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) { return a.time_us < b.time_us; });
    return frames;
}

double percentile(std::vector<double> values, double p) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    const auto i = static_cast<std::size_t>(p / 100.0 * static_cast<double>(values.size() - 1));
    return values[i];
}

std::uint64_t key(const Frame& f) {
    std::uint64_t k = f.bytes.size();
    for (std::size_t i = 7; i < 12 && i < f.bytes.size(); ++i) k = (k << 8) | f.bytes[i];
    return k;
}

int delay(const std::string& in_file, const std::string& out_file) {
    const auto in = read(in_file);
    const auto out = read(out_file);
    std::map<std::uint64_t, double> last_in;  // key -> time of the newest IN frame seen so far
    std::vector<double> delays;
    std::size_t i = 0;
    for (const auto& f : out) {
        for (; i < in.size() && in[i].time_us <= f.time_us; ++i) last_in[key(in[i])] = in[i].time_us;
        const auto it = last_in.find(key(f));
        // A frame id comes back every few cycles; only a recent match is this frame.
        if (it != last_in.end() && f.time_us - it->second < 1000.0) delays.push_back(f.time_us - it->second);
    }
    std::printf("frames matched: %zu of %zu\n", delays.size(), out.size());
    std::printf("delay p50 %.1f us, p99 %.1f us, max %.1f us\n", percentile(delays, 50), percentile(delays, 99),
                delays.empty() ? 0.0 : *std::max_element(delays.begin(), delays.end()));
    return delays.empty() ? 1 : 0;
}

int gaps(const std::string& file, double cycle_us) {
    const auto capture = ecpair::test::read_segment_capture(file);
    if (!capture) {
        std::fprintf(stderr, "%s\n", capture.error().c_str());
        return 2;
    }
    const auto handovers = capture->handovers();
    std::vector<double> all;
    const double first = capture->first_us();
    for (std::size_t i = 0; i < handovers.size(); ++i) {
        const auto& h = handovers[i];
        all.push_back(h.gap_us);
        std::printf("takeover %zu at %.3f s: %06x -> %06x, %.2f ms without process data", i + 1,
                    (h.at_us - first) / 1e6, h.from, h.to, h.gap_us / 1000.0);
        if (cycle_us > 0) std::printf(" (%.1f cycles)", h.gap_us / cycle_us);
        std::printf("\n");
    }
    if (!all.empty()) {
        std::printf("takeovers: %zu, gap min %.2f ms, p50 %.2f ms, max %.2f ms\n", all.size(),
                    *std::min_element(all.begin(), all.end()) / 1000.0, percentile(all, 50) / 1000.0,
                    *std::max_element(all.begin(), all.end()) / 1000.0);
    }
    std::printf("cycles no master numbered: %zu; cycles two masters numbered: %zu\n", capture->missing_cycles().size(),
                capture->doubled_cycles().size());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "delay" && argc == 4) return delay(argv[2], argv[3]);
    if (mode == "gaps" && (argc == 3 || argc == 4)) return gaps(argv[2], argc == 4 ? std::atof(argv[3]) : 0.0);
    std::fprintf(stderr, "usage: %s delay IN.pcap OUT.pcap | gaps SEGMENT.pcap [CYCLE_US]\n", argv[0]);
    return 2;
}
