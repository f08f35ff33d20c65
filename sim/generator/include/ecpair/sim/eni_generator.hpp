#pragma once
// Writes a synthetic but complete ENI for a line of simple IO slaves without
// mailbox: every slave has `output_bytes` of outputs (SM2 at 0x1100, FMMU 0
// write) and `input_bytes` of inputs (SM3 at 0x1400, FMMU 1 read) in one
// logical range; the cyclic frame uses LWR + LRD (so it works with cable
// redundancy as is) split into datagrams of at most 1486 bytes, plus a BRD
// of AL status. InitCmds follow EC-Engineer's pattern (state requests with
// Validate on AL status, station addresses, SMs, FMMUs). Used by benchmarks
// and tests that need sizes no shared ENI has (33 slaves, 5 kB).

#include <cstdint>
#include <string>

namespace ecpair::sim {

struct GeneratedEniOptions {
    std::uint32_t slaves = 33;
    std::uint32_t input_bytes = 76;   // per slave
    std::uint32_t output_bytes = 76;  // per slave
    std::uint32_t cycle_time_us = 1000;
    std::uint32_t logical_base = 0x10000000;
    std::uint32_t vendor_id = 0x00000E5C;  // not a registered vendor: a simulator's own
    std::uint32_t product_code = 0x00010001;
    std::uint32_t revision_no = 0x00010000;
};

// The ENI as XML text.
std::string generate_eni(const GeneratedEniOptions& options);

}  // namespace ecpair::sim
