#pragma once
// Writes Ethernet frames to a classic pcap file (DLT_EN10MB), as ecsim's
// --pcap option does for every frame in and out of the segment. Frames are
// buffered by libpcap; flush() pushes them to the file, and the destructor
// flushes and closes it. Recording allocates nothing.

#include <chrono>
#include <memory>
#include <string>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"

namespace ecpair::sim {

struct PcapError {
    std::string message;  // names the file and libpcap's reason
};

class PcapRecorder {
public:
    static Expected<PcapRecorder, PcapError> create(const std::string& path);

    PcapRecorder(PcapRecorder&&) noexcept;
    PcapRecorder& operator=(PcapRecorder&&) noexcept;
    ~PcapRecorder();

    void record(ConstBytes frame, std::chrono::system_clock::time_point when);
    void flush();
    // Whether frames were recorded since the last flush.
    bool has_unflushed() const { return unflushed_; }
    const std::string& path() const { return path_; }

private:
    struct Handles;
    PcapRecorder(std::string path, std::unique_ptr<Handles> handles);

    std::string path_;
    std::unique_ptr<Handles> handles_;
    bool unflushed_ = false;
};

}  // namespace ecpair::sim
