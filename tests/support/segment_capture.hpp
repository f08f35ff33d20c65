#pragma once
// What the slaves received, read back from ecsim's --pcap capture (every
// frame into and out of the simulated segment). For the failover tests and
// the benchmarks: when process data arrived and from which master, which
// cycles the masters' Cyclic Master Red Frames numbered, and the gaps
// between them.
//
// A master is named by the NIC bytes (source MAC bytes 3-5) of its MAIN
// adapter; the copy it sends on RED carries its RED adapter's bytes and is
// attributed to it through the frame id both copies share. A delivery is one
// frame that reached the slaves (its first copy into the segment); ESCs only
// change source MAC byte 0, so copies on their way out are recognised too.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"

namespace ecpair::test {

struct Delivery {
    double time_us = 0;        // first copy into the segment
    std::uint32_t master = 0;  // NIC bytes of the sender's MAIN adapter (its RED adapter's, when unpaired)
};

struct Handover {
    double at_us = 0;  // the new master's first delivery
    std::uint32_t from = 0;
    std::uint32_t to = 0;
    double gap_us = 0;  // since the old master's last delivery
};

struct SegmentCapture {
    std::vector<Delivery> process_data;  // frames with LWR, LRD or LRW, in time order
    // Cycle numbers of the CMFs each master sent (the header's 64-bit counter), by the sender's MAIN MAC.
    std::map<std::uint64_t, std::set<std::uint64_t>> cmf_cycles;

    // Deliveries from `from_us` on (all when 0).
    std::vector<Handover> handovers(double from_us = 0) const;
    // The longest time between two deliveries within [from_us, to_us].
    double longest_gap_us(double from_us = 0, double to_us = 1e300) const;
    double first_us() const { return process_data.empty() ? 0 : process_data.front().time_us; }
    double last_us() const { return process_data.empty() ? 0 : process_data.back().time_us; }
    // Cycle numbers between the lowest and the highest any master's CMF
    // carried that no CMF carried (cycles without a master), and those two
    // masters both numbered (cycles with two).
    std::vector<std::uint64_t> missing_cycles(std::uint64_t from_cycle = 0) const;
    // Cycles from `from_cycle` on that CMFs of two masters carry.
    std::vector<std::uint64_t> doubled_cycles(std::uint64_t from_cycle = 0) const;
};

// Reads an ecsim capture; the error names the file.
Expected<SegmentCapture, std::string> read_segment_capture(const std::string& pcap_file);

}  // namespace ecpair::test
