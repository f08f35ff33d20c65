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
//       master or two masters sent. Changes that follow each other within
//       five cycles (both masters delivering at once: the two halves of a
//       double line break, or a collision) are one "two masters" period,
//       not a series of takeovers; a single frame of one master amid the
//       other's is reported as a stray frame.
//   cadence SEGMENT.pcap FROM_US TO_US CYCLE_US [stretches]
//       The cyclic frames at the slaves in a time window (Unix µs), for the
//       Hot-Connect benchmark: the MAIN copies of process-data frames as they
//       entered the segment (source MAC byte 0 without the slave-forwarding
//       and redundancy bits), their largest gap and the cycles missing (a gap
//       of k cycles misses k-1); and the WKCs of their LRD datagrams as they
//       came out processed (bit 0x02 set), lowest and highest. With
//       `stretches` after CYCLE_US: how many stretches were longer than 5
//       cycles, then a line "stretch END_US LENGTH_US" each.

#include <pcap/pcap.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"
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
    const double first = capture->first_us();
    const double together_us = 5 * (cycle_us > 0 ? cycle_us : 1000.0);
    const auto seconds = [first](double us) { return (us - first) / 1e6; };
    std::vector<double> takeover_gaps;
    std::size_t takeovers = 0;
    for (std::size_t i = 0; i < handovers.size();) {
        // A run of changes each within together_us of the one before it.
        std::size_t end = i + 1;
        while (end < handovers.size() && handovers[end].at_us - handovers[end - 1].at_us <= together_us) ++end;
        if (end - i >= 3) {
            std::printf("two masters delivering from %.3f s to %.3f s (%zu changes): a double line break or a "
                        "collision; then %06x alone\n",
                        seconds(handovers[i].at_us), seconds(handovers[end - 1].at_us), end - i, handovers[end - 1].to);
            i = end;
            continue;
        }
        if (end - i == 2 && handovers[i].from == handovers[i + 1].to) {
            // One delivery attributed to the other master amid this one's: not a takeover.
            std::printf("a stray frame from %06x amid %06x's at %.3f s\n", handovers[i].to, handovers[i].from,
                        seconds(handovers[i].at_us));
            i = end;
            continue;
        }
        const auto& h = handovers[i++];
        takeover_gaps.push_back(h.gap_us);
        std::printf("takeover %zu at %.3f s: %06x -> %06x, %.2f ms without process data", ++takeovers, seconds(h.at_us),
                    h.from, h.to, h.gap_us / 1000.0);
        if (cycle_us > 0) std::printf(" (%.1f cycles)", h.gap_us / cycle_us);
        std::printf("\n");
    }
    if (!takeover_gaps.empty()) {
        std::printf("takeovers: %zu, gap min %.2f ms, p50 %.2f ms, max %.2f ms (times from the first process data)\n",
                    takeover_gaps.size(), *std::min_element(takeover_gaps.begin(), takeover_gaps.end()) / 1000.0,
                    percentile(takeover_gaps, 50) / 1000.0,
                    *std::max_element(takeover_gaps.begin(), takeover_gaps.end()) / 1000.0);
    }
    std::printf("longest time without process data: %.2f ms\n", capture->longest_gap_us() / 1000.0);
    std::printf("cycles no master numbered: %zu; cycles two masters numbered: %zu\n", capture->missing_cycles().size(),
                capture->doubled_cycles().size());
    return 0;
}

bool carries_process_data(const Frame& f) {
    auto view = wire::ConstFrameView::parse(f.bytes);
    if (!view) return false;
    return std::any_of(view->begin(), view->end(), [](const auto& d) {
        return d.command() == wire::Command::Lrd || d.command() == wire::Command::Lwr || d.command() == wire::Command::Lrw;
    });
}

int cadence(const std::string& file, double from_us, double to_us, double cycle_us, bool list_stretches) {
    const auto frames = read(file);
    std::vector<double> entered;
    int wkc_min = -1;
    int wkc_max = -1;
    for (const auto& f : frames) {
        if (f.time_us < from_us || f.time_us > to_us || f.bytes.size() < 12 || !carries_process_data(f)) continue;
        const std::uint8_t byte0 = f.bytes[6];
        if ((byte0 & wire::SourceMac::kRedundancyBit) != 0) continue;
        if ((byte0 & 0x02) == 0) {
            entered.push_back(f.time_us);
            continue;
        }
        auto view = wire::ConstFrameView::parse(f.bytes);
        for (const auto d : *view) {
            if (d.command() != wire::Command::Lrd) continue;
            const int wkc = d.wkc();
            wkc_min = wkc_min < 0 ? wkc : std::min(wkc_min, wkc);
            wkc_max = std::max(wkc_max, wkc);
        }
    }
    double largest = 0;
    long missing = 0;
    std::vector<std::pair<double, double>> stretches;  // longer than 5 cycles: (end in Unix µs, length)
    for (std::size_t i = 1; i < entered.size(); ++i) {
        const double gap = entered[i] - entered[i - 1];
        largest = std::max(largest, gap);
        const long cycles = std::lround(gap / cycle_us);
        if (cycles > 1) missing += cycles - 1;
        if (gap > 5 * cycle_us) stretches.emplace_back(entered[i], gap);
    }
    std::printf("frames %zu in %.1f ms, largest gap %.0f us, cycles missing %ld, LRD WKC %d..%d\n", entered.size(),
                (to_us - from_us) / 1000.0, largest, missing, wkc_min, wkc_max);
    if (list_stretches) {
        std::printf("stretches without process data longer than 5 cycles: %zu\n", stretches.size());
        for (const auto& [end, length] : stretches) std::printf("stretch %.0f %.0f\n", end, length);
    }
    return entered.empty() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "delay" && argc == 4) return delay(argv[2], argv[3]);
    if (mode == "gaps" && (argc == 3 || argc == 4)) return gaps(argv[2], argc == 4 ? std::atof(argv[3]) : 0.0);
    if (mode == "cadence" && (argc == 6 || (argc == 7 && std::string(argv[6]) == "stretches"))) {
        return cadence(argv[2], std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5]), argc == 7);
    }
    std::fprintf(stderr,
                 "usage: %s delay IN.pcap OUT.pcap | gaps SEGMENT.pcap [CYCLE_US] | cadence SEGMENT.pcap FROM_US TO_US "
                 "CYCLE_US [stretches]\n",
                 argv[0]);
    return 2;
}
