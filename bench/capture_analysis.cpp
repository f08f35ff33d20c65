// ecpair-capture-analysis: figures from packet captures (libpcap files), for
// the redundancy benchmarks.
//
//   delay IN.pcap OUT.pcap
//       Store-and-forward delay: for every frame in OUT, the frame in IN with
//       the same source MAC bytes 1-5 (frame id, NIC bytes) and length that
//       arrived last before it; prints p50/p99/max of OUT - IN in µs.
//       (Byte 0 may differ: the forwarding bits.)
//   gaps SEGMENT.pcap
//       Takeover gaps from ecsim's --pcap: the MAIN copies (redundancy bit
//       clear) of frames carrying process data (LRD/LWR/LRW), grouped by the
//       MAIN adapter that sent them (source MAC bytes 3-5), so one master is
//       one group; every change of group is a takeover and its gap the time
//       from the last frame of the old master to the first of the new one.

#include <pcap/pcap.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

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

bool carries_process_data(const Frame& f) {
    auto view = wire::ConstFrameView::parse(f.bytes);
    if (!view) return false;
    return std::any_of(view->begin(), view->end(), [](const auto& d) {
        return d.command() == wire::Command::Lrd || d.command() == wire::Command::Lwr || d.command() == wire::Command::Lrw;
    });
}

int gaps(const std::string& file) {
    const auto frames = read(file);
    std::uint32_t master = 0;
    double last = 0;
    int takeovers = 0;
    std::vector<double> all;
    for (const auto& f : frames) {
        if (f.bytes.size() < 12 || (f.bytes[6] & wire::SourceMac::kRedundancyBit) != 0 || !carries_process_data(f)) {
            continue;
        }
        // The NIC bytes say which master sent it; ESCs only change byte 0.
        const std::uint32_t nic = (std::uint32_t{f.bytes[9]} << 16) | (std::uint32_t{f.bytes[10]} << 8) | f.bytes[11];
        if (master != 0 && nic != master && f.time_us - last > 0) {
            ++takeovers;
            all.push_back(f.time_us - last);
            std::printf("takeover %d: %.0f us without process data\n", takeovers, f.time_us - last);
        }
        master = nic;
        last = f.time_us;
    }
    if (!all.empty()) {
        std::printf("takeovers: %d, gap min %.0f us, p50 %.0f us, max %.0f us\n", takeovers,
                    *std::min_element(all.begin(), all.end()), percentile(all, 50), *std::max_element(all.begin(), all.end()));
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "delay" && argc == 4) return delay(argv[2], argv[3]);
    if (mode == "gaps" && argc == 3) return gaps(argv[2]);
    std::fprintf(stderr, "usage: %s delay IN.pcap OUT.pcap | gaps SEGMENT.pcap\n", argv[0]);
    return 2;
}
