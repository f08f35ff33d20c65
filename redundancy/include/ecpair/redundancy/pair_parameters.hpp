#pragma once
// What both masters of a redundant pair must agree on before one can be the
// other's hot standby (design.md §1): the same ENI, the same cycle and the
// same redundancy parameters. The ACTIVE puts them, with their fingerprint,
// into the header of every Cyclic Master Red Frame; the INACTIVE compares
// the fingerprint with its own and, when they differ, names what differs.
//
// Encoding (docs/WIRE_FORMAT.md §4), 28 bytes, little-endian:
//   0  u64  ENI content hash (EniConfig::content_hash)
//   8  u64  cycle time in nanoseconds
//   16 u32  master_pd_out_size (ACTIVE->INACTIVE bytes)
//   20 u32  master_pd_in_size (INACTIVE->ACTIVE bytes)
//   24 u16  max_acyc_frames_per_cycle
//   26 u8   flags: b0 cable redundancy, b1 split LRW, b2 update slave PD in, b3 update slave PD out
//   27 u8   reserved, 0
// fingerprint() is FNV-1a 64 over exactly these 28 bytes.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"

namespace ecpair::redundancy {

struct PairParameters {
    static constexpr std::size_t kEncodedSize = 28;

    std::uint64_t eni_content_hash = 0;
    std::chrono::nanoseconds cycle_time{0};
    bool cable_redundancy = false;
    bool split_lrw = false;
    std::uint32_t master_pd_out_size = 0;  // ACTIVE -> INACTIVE master process data
    std::uint32_t master_pd_in_size = 0;   // INACTIVE -> ACTIVE master process data
    bool update_slave_pd_in = false;
    bool update_slave_pd_out = false;
    std::uint16_t max_acyc_frames_per_cycle = 0;

    // out.size() >= kEncodedSize.
    void encode(Bytes out) const;
    // in.size() >= kEncodedSize. Reserved bits are not kept (CmfHeader::decode
    // refuses parameters that set any).
    static PairParameters decode(ConstBytes in);

    // Stable across builds and hosts: FNV-1a 64 over encode().
    std::uint64_t fingerprint() const;

    friend bool operator==(const PairParameters&, const PairParameters&) = default;
};

// Human names of what differs, ours first: "ENI (content hash 0x... vs 0x...)",
// "cycle time 1000 µs vs 500 µs", "cable redundancy on vs off", ...
// Empty when the parameters are equal.
std::vector<std::string> differences(const PairParameters& ours, const PairParameters& theirs);

}  // namespace ecpair::redundancy
