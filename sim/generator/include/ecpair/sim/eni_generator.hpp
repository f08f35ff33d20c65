#pragma once
// Writes a synthetic but complete ENI for a line of simple IO slaves without
// mailbox: every slave has `output_bytes` of outputs (SM2 at 0x1100, FMMU 0
// write) and `input_bytes` of inputs (SM3 at 0x1400, FMMU 1 read) in one
// logical range; the cyclic frame uses LWR + LRD (so it works with cable
// redundancy as is) split into datagrams of at most 1486 bytes, plus a BRD
// of AL status. InitCmds follow EC-Engineer's pattern (state requests with
// Validate on AL status, station addresses, SMs, FMMUs). Used by benchmarks
// and tests that need sizes no shared ENI has (33 slaves, 5 kB).
//
// With `groups` > 0 the first `groups` slaves of the line are junctions
// (four ports, as an EK1122 adds) and Hot-Connect group k hangs off port D
// of junction k: `group_slaves` slaves in a line behind their head, which
// carries the group's identification (value 100 + k) and an IdentifyCmd
// where the mode allows one (the alias). Floating groups name no
// PreviousPort and come after the line (ecsim starts them unplugged). CoE
// groups are drives: a mailbox, CoE, and SDO InitCmds in PS. Ring order
// (AutoIncAddr) is the order a frame visits everything plugged in:
// junction k, then group k, then junction k+1.

#include <cstdint>
#include <optional>
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

    enum class Identification : std::uint8_t { None, StationAlias, ExplicitDeviceId, InputWord };
    std::uint32_t groups = 0;        // Hot-Connect groups (at most `slaves`)
    std::uint32_t group_slaves = 4;  // slaves per group
    Identification identification = Identification::StationAlias;
    bool floating = false;           // the groups float
    bool coe_groups = false;         // group slaves are CoE drives
};

inline constexpr std::uint32_t kGroupHeadProduct = 0x00020001;
inline constexpr std::uint32_t kGroupMemberProduct = 0x00020002;
inline constexpr std::uint32_t kGroupIdentificationBase = 100;  // group k is identified by 100 + k

// What options are wrong, in words ("--groups 3 needs at least 3 slaves"); nullopt when fine.
std::optional<std::string> check_options(const GeneratedEniOptions& options);

// The ENI as XML text.
std::string generate_eni(const GeneratedEniOptions& options);

}  // namespace ecpair::sim
