#include "segment_capture.hpp"

#include <pcap/pcap.h>

#include <algorithm>
#include <optional>

#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace ecpair::test {
namespace {

struct Copy {
    double time_us;
    std::uint8_t byte0;
    std::uint8_t frame_id;
    std::uint32_t nic;
    bool process_data;
    std::optional<redundancy::CmfHeader> header;
};

std::uint32_t nic_of(const std::uint8_t* source) {
    return (std::uint32_t{source[3]} << 16) | (std::uint32_t{source[4]} << 8) | source[5];
}

std::optional<Copy> decode(double time_us, ConstBytes frame) {
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return std::nullopt;
    Copy copy{time_us, frame[6], frame[7], nic_of(frame.data() + 6), false, std::nullopt};
    for (const auto d : *view) {
        const auto c = d.command();
        if (c == wire::Command::Lrd || c == wire::Command::Lwr || c == wire::Command::Lrw) copy.process_data = true;
        if (!copy.header && redundancy::is_cmf_datagram(d)) {
            const auto data = d.data();
            const auto segment = redundancy::CmfSegmentHeader::decode(data, 0);
            if (segment && segment->kind == redundancy::CmfKind::Header && segment->offset == 0) {
                if (auto h = redundancy::CmfHeader::decode(data.subspan(redundancy::CmfSegmentHeader::kSize), 0)) {
                    copy.header = *h;
                }
            }
        }
    }
    return copy;
}

std::uint64_t mac_number(const wire::MacAddress& mac) {
    std::uint64_t v = 0;
    for (const auto b : mac.bytes) v = (v << 8) | b;
    return v;
}

}  // namespace

Expected<SegmentCapture, std::string> read_segment_capture(const std::string& pcap_file) {
    char error[PCAP_ERRBUF_SIZE];
    pcap_t* pcap = pcap_open_offline(pcap_file.c_str(), error);
    if (pcap == nullptr) return unexpected(pcap_file + ": " + error);
    std::vector<Copy> copies;
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    while (pcap_next_ex(pcap, &header, &data) == 1) {
        const double t = static_cast<double>(header->ts.tv_sec) * 1e6 + static_cast<double>(header->ts.tv_usec);
        if (auto copy = decode(t, ConstBytes(data, header->caplen))) copies.push_back(*copy);
    }
    pcap_close(pcap);
    std::stable_sort(copies.begin(), copies.end(), [](const Copy& a, const Copy& b) { return a.time_us < b.time_us; });

    SegmentCapture out;
    // Copies of one frame share its frame id and arrive close together: its
    // MAIN and RED copy, and each of them into and out of the segment. The
    // first is the delivery; a MAIN copy (redundancy bit clear) next to a RED
    // one tells which RED adapter belongs to which master.
    constexpr double kSameFrameUs = 400;
    struct Seen {
        double time_us;
        std::uint32_t nic;
        bool red;
    };
    std::map<std::uint8_t, std::vector<Seen>> recent;  // by frame id
    // How often each RED adapter's copy came with each MAIN adapter's: two
    // masters sending at once (a collision, a double line break) now and then
    // pair copies of different masters that happen to share a frame id, so the
    // pairing seen most often names the RED adapter's master.
    std::map<std::uint32_t, std::map<std::uint32_t, std::size_t>> red_with_main;
    for (const auto& copy : copies) {
        if (copy.header) out.cmf_cycles[mac_number(copy.header->sender.member)].insert(copy.header->cycle);
        if (!copy.process_data) continue;
        const bool red = (copy.byte0 & wire::SourceMac::kRedundancyBit) != 0;
        auto& same_id = recent[copy.frame_id];
        std::erase_if(same_id, [&](const Seen& s) { return copy.time_us - s.time_us > kSameFrameUs; });
        bool delivered = false;
        for (const auto& s : same_id) {
            if (s.nic == copy.nic) delivered = true;
            if (s.red != red) {
                ++red_with_main[red ? copy.nic : s.nic][red ? s.nic : copy.nic];
                delivered = true;
            }
        }
        same_id.push_back({copy.time_us, copy.nic, red});
        if (!delivered) out.process_data.push_back({copy.time_us, copy.nic});
    }
    std::map<std::uint32_t, std::uint32_t> red_to_main;
    for (const auto& [red_nic, mains] : red_with_main) {
        red_to_main[red_nic] =
            std::max_element(mains.begin(), mains.end(), [](const auto& a, const auto& b) { return a.second < b.second; })
                ->first;
    }
    for (auto& d : out.process_data) {
        if (const auto it = red_to_main.find(d.master); it != red_to_main.end()) d.master = it->second;
    }
    return out;
}

std::vector<Handover> SegmentCapture::handovers(double from_us) const {
    std::vector<Handover> out;
    const Delivery* previous = nullptr;
    for (const auto& d : process_data) {
        if (d.time_us < from_us) continue;
        if (previous && d.master != previous->master) {
            out.push_back({d.time_us, previous->master, d.master, d.time_us - previous->time_us});
        }
        previous = &d;
    }
    return out;
}

double SegmentCapture::longest_gap_us(double from_us, double to_us) const {
    double longest = 0;
    const Delivery* previous = nullptr;
    for (const auto& d : process_data) {
        if (d.time_us < from_us || d.time_us > to_us) continue;
        if (previous) longest = std::max(longest, d.time_us - previous->time_us);
        previous = &d;
    }
    return longest;
}

std::vector<std::uint64_t> SegmentCapture::missing_cycles(std::uint64_t from_cycle) const {
    std::set<std::uint64_t> all;
    for (const auto& [master, cycles] : cmf_cycles) all.insert(cycles.begin(), cycles.end());
    std::vector<std::uint64_t> missing;
    if (all.empty()) return missing;
    const auto first = std::max(from_cycle, *all.begin());
    for (auto c = first; c <= *all.rbegin(); ++c) {
        if (!all.contains(c)) missing.push_back(c);
    }
    return missing;
}

std::vector<std::uint64_t> SegmentCapture::doubled_cycles(std::uint64_t from_cycle) const {
    std::map<std::uint64_t, int> senders;
    for (const auto& [master, cycles] : cmf_cycles) {
        for (auto c = cycles.lower_bound(from_cycle); c != cycles.end(); ++c) ++senders[*c];
    }
    std::vector<std::uint64_t> doubled;
    for (const auto& [cycle, n] : senders) {
        if (n > 1) doubled.push_back(cycle);
    }
    return doubled;
}

}  // namespace ecpair::test
