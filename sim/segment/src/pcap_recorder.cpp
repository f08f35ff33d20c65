// pcap file writing through libpcap: a "dead" pcap handle supplies the link
// type and snapshot length, pcap_dump_open() the file. The snapshot length
// covers the largest frame, so nothing is ever cut.

#include "ecpair/sim/pcap_recorder.hpp"

#include <pcap/pcap.h>

#include <fmt/format.h>

namespace ecpair::sim {

namespace {
constexpr int kSnapshotLength = 65535;
}

struct PcapRecorder::Handles {
    pcap_t* pcap = nullptr;
    pcap_dumper_t* dumper = nullptr;

    ~Handles() {
        if (dumper != nullptr) {
            pcap_dump_flush(dumper);
            pcap_dump_close(dumper);
        }
        if (pcap != nullptr) pcap_close(pcap);
    }
};

Expected<PcapRecorder, PcapError> PcapRecorder::create(const std::string& path) {
    auto handles = std::make_unique<Handles>();
    handles->pcap = pcap_open_dead(DLT_EN10MB, kSnapshotLength);
    if (handles->pcap == nullptr) {
        return unexpected(PcapError{fmt::format("{}: libpcap cannot create a capture handle", path)});
    }
    handles->dumper = pcap_dump_open(handles->pcap, path.c_str());
    if (handles->dumper == nullptr) {
        return unexpected(PcapError{fmt::format("{}: cannot open for writing: {}", path, pcap_geterr(handles->pcap))});
    }
    return PcapRecorder(path, std::move(handles));
}

PcapRecorder::PcapRecorder(std::string path, std::unique_ptr<Handles> handles)
    : path_(std::move(path)), handles_(std::move(handles)) {}

PcapRecorder::PcapRecorder(PcapRecorder&&) noexcept = default;
PcapRecorder& PcapRecorder::operator=(PcapRecorder&&) noexcept = default;
PcapRecorder::~PcapRecorder() = default;

void PcapRecorder::record(ConstBytes frame, std::chrono::system_clock::time_point when) {
    const auto since_epoch = std::chrono::duration_cast<std::chrono::microseconds>(when.time_since_epoch());
    pcap_pkthdr header{};
    header.ts.tv_sec = static_cast<time_t>(since_epoch.count() / 1'000'000);
    header.ts.tv_usec = static_cast<suseconds_t>(since_epoch.count() % 1'000'000);
    header.caplen = static_cast<bpf_u_int32>(frame.size());
    header.len = static_cast<bpf_u_int32>(frame.size());
    pcap_dump(reinterpret_cast<u_char*>(handles_->dumper), &header, frame.data());
    unflushed_ = true;
}

void PcapRecorder::flush() {
    pcap_dump_flush(handles_->dumper);
    unflushed_ = false;
}

}  // namespace ecpair::sim
