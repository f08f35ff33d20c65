#pragma once
// What the master sends every cycle, derived once from the ENI's <Cyclic>
// section: frames of datagrams, each with its expected working counter and
// where its data comes from (output image) and goes to (input image).
//
// Two offset conventions exist in real files (eni-structure.md):
//  - compact (EC-Engineer): InputOffs/OutputOffs are the data's byte offset
//    in the image;
//  - frame image (TwinCAT): the image is a copy of the Ethernet frame and
//    the offsets point at the datagram header, so data starts 10 bytes later.
// The plan resolves both into plain data offsets.
//
// With cable redundancy LRW cannot be used (the unprocessed copy would be
// ORed into the inputs): the plan refuses LRW, or with split_lrw replaces
// every LRW by an LWR and an LRD over the same logical range, with expected
// WKCs counted from the slaves' FMMU directions in the ENI. Those must add
// up to the LRW's <Cnt> (writers * 2 + readers): where they do not (FMMU
// records that do not map the range), the plan is refused rather than run
// with an expected WKC the ENI does not give (0 for unmapped process data
// would hide that nothing is exchanged).
//
// A datagram's WKC is checked only from the state in which it can be right
// (valid_from): process data runs from SAFEOP, whatever states an ENI lists
// its commands in (Panasonic lists them in PREOP too); a logical range of
// registers (the mailbox-state FMMUs) from the state its FMMUs are set in.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::master {

enum class OffsetConvention : std::uint8_t { Compact, FrameImage };
std::string_view to_string(OffsetConvention convention);

struct PlannedDatagram {
    wire::Command command = wire::Command::Nop;
    std::uint32_t address = 0;  // ADP|ADO<<16 or logical
    std::uint16_t length = 0;
    std::optional<std::uint16_t> expected_wkc;
    std::optional<std::uint32_t> input_offset;   // read data goes here in the input image
    std::optional<std::uint32_t> output_offset;  // written data comes from here in the output image
    eni::StateSet states;
    std::string comment;
    int source_line = 0;
    bool split_from_lrw = false;
    eni::SlaveState valid_from = eni::SlaveState::Preop;  // its WKC is checked in this state and above
};

struct PlannedFrame {
    std::vector<PlannedDatagram> datagrams;
};

struct PlanOptions {
    bool cable_redundancy = false;
    bool split_lrw = false;
};

struct PlanError {
    std::string message;  // names the commands (ENI line, comment) that caused it
};

struct CyclicPlan {
    OffsetConvention convention = OffsetConvention::Compact;
    std::size_t input_image_size = 0;   // bytes the mappings need
    std::size_t output_image_size = 0;
    std::vector<PlannedFrame> frames;

    static Expected<CyclicPlan, PlanError> build(const eni::EniConfig& eni, const PlanOptions& options);

    std::size_t datagram_count() const;
};

// How many slaves of the ENI read (LRD side) and write (LWR side) the
// logical range [address, address + length), from their FMMU InitCmds.
struct FmmuDirections {
    std::uint16_t readers = 0;
    std::uint16_t writers = 0;
};
FmmuDirections fmmu_directions(const eni::EniConfig& eni, std::uint32_t address, std::size_t length);

// The lowest state in which a logical datagram over [address, address +
// length) can get its WKC: SAFEOP when an FMMU maps it to process RAM (or
// none maps it), else the state the FMMUs mapping it are written on the way to.
eni::SlaveState logical_range_valid_from(const eni::EniConfig& eni, std::uint32_t address, std::size_t length);

}  // namespace ecpair::master
