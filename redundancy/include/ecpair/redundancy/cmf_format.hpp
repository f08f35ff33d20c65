#pragma once
// The Cyclic Master Red Frame format, version 2 (docs/WIRE_FORMAT.md).
//
// A CMF is what the ACTIVE tells its standby every cycle, in NOP datagrams
// addressed ADP 0 / ADO 0x4155 that no slave processes. The content is cut
// into sections (HEADER, SLAVE_STATE_IMAGE, SHADOW_INPUTS, MASTER_PD_OUT,
// MASTER_PD_IN, STANDBY_STATUS); every datagram carries one piece of one section behind a
// 16-byte segment header (kind, part number, byte offset, cycle) so that a
// receiver can place it without context. How the sections are cut into
// datagrams and frames is fixed by the layout (CmfPlan): both masters of a
// pair compute the same plan from the same ENI and parameters.
//
// This header holds the wire types and their encode/decode; cmf_writer.hpp
// builds the frames, cmf_assembler.hpp puts received parts together,
// cmf_inactive.hpp is what the INACTIVE does to a CMF it forwards.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/slave_state_image.hpp"
#include "ecpair/redundancy/pair_parameters.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::redundancy {

inline constexpr std::uint8_t kCmfFormatVersion = 2;

// The sections, in the order the plan lays them out.
enum class CmfKind : std::uint8_t {
    Header = 1,
    SlaveStateImage = 2,
    ShadowInputs = 3,
    MasterPdOut = 4,  // ACTIVE -> INACTIVE master process data
    MasterPdIn = 5,   // INACTIVE -> ACTIVE master process data, filled in by the INACTIVE
    StandbyStatus = 6,  // INACTIVE -> ACTIVE: what kind of standby it is (CmfStandbyStatus), filled in by the INACTIVE
};
inline constexpr std::array<CmfKind, 6> kCmfKinds{CmfKind::Header,      CmfKind::SlaveStateImage,
                                                  CmfKind::ShadowInputs, CmfKind::MasterPdOut,
                                                  CmfKind::MasterPdIn,   CmfKind::StandbyStatus};

// ---- errors

enum class CmfErrc : std::uint8_t {
    Truncated,           // fewer bytes than the structure needs
    BadMagic,            // the segment does not start with "CM"
    UnsupportedVersion,  // a format version other than kCmfFormatVersion
    UnknownKind,         // a section kind outside 1..5
    InvalidMasterState,  // the header's master state is no AL state
    InconsistentHeader,  // the header's sizes or part count contradict each other or the segment
    FingerprintCorrupt,  // the header's fingerprint is not the fingerprint of its parameters
    ReservedBitsSet,     // the pair parameters use bits this version does not know
    CycleMismatch,       // the header's cycle counter disagrees with its segment header
    PartnerDiffers,      // the partner's ENI or parameters differ from ours (fingerprints differ)
    LayoutMismatch,      // the partner's sections have other sizes than ours
    BadPlacement,        // a part's kind, offset or length is not where the layout puts it
};
std::string_view to_string(CmfErrc code);

struct CmfError {
    CmfErrc code = CmfErrc::Truncated;
    std::size_t offset = 0;     // byte offset from the start of the Ethernet frame (or of the decoded bytes)
    std::uint64_t found = 0;    // the offending value
    std::uint64_t expected = 0; // what was expected instead, where that is one value

    // "CMF LayoutMismatch at frame offset 46: found 3, expected 4"
    std::string describe() const;
};

// ---- the segment header in front of every CMF datagram's payload

struct CmfSegmentHeader {
    static constexpr std::size_t kSize = 16;
    static constexpr std::array<std::uint8_t, 2> kMagic{'C', 'M'};

    std::uint8_t version = kCmfFormatVersion;
    CmfKind kind = CmfKind::Header;
    std::uint16_t part = 0;        // 0..part_count-1, the datagram's place in this cycle's CMF
    std::uint16_t part_count = 0;  // datagrams in this cycle's CMF
    std::uint32_t offset = 0;      // where the payload goes in its section
    std::uint32_t cycle_low = 0;   // the cycle counter's low 32 bits

    void encode(Bytes out) const;  // out.size() >= kSize
    // `data` is the datagram's data; `data_offset` its offset in the frame (for errors).
    // Checks size, magic, version, kind and part < part_count.
    static Expected<CmfSegmentHeader, CmfError> decode(ConstBytes data, std::size_t data_offset);

    friend bool operator==(const CmfSegmentHeader&, const CmfSegmentHeader&) = default;
};

// A NOP datagram at ADP 0 / ADO 0x4155 whose data starts with the CMF magic.
bool is_cmf_datagram(const wire::ConstDatagramView& datagram);
bool is_cmf_datagram(const wire::DatagramView& datagram);

// ---- layout: section sizes and how they are cut into datagrams and frames

struct CmfLayout {
    PairParameters parameters;  // the master PD sizes come from here
    std::uint16_t slave_count = 0;
    std::uint32_t shadow_inputs_size = 0;

    std::uint32_t section_size(CmfKind kind) const;
    friend bool operator==(const CmfLayout&, const CmfLayout&) = default;
};

// One datagram of a CMF: which piece of which section, in which frame.
struct CmfPart {
    CmfKind kind = CmfKind::Header;
    std::uint16_t frame = 0;   // 0-based frame of the cycle's CMF
    std::uint32_t offset = 0;  // in the section
    std::uint32_t length = 0;  // payload bytes (the datagram's data is kSize more)
    friend bool operator==(const CmfPart&, const CmfPart&) = default;
};

// The parts of a layout in wire order (WIRE_FORMAT.md §3): sections in kind
// order, each cut greedily so that every frame is filled to its 1498-byte
// EtherCAT payload before the next begins. Made once, outside the cycle.
class CmfPlan {
public:
    static constexpr std::size_t kMaxParts = 0xFFFF;

    // Fails when the layout needs more than kMaxParts datagrams.
    static Expected<CmfPlan, std::string> make(const CmfLayout& layout);
    // Parts the layout needs, counted without allocating; stops counting past kMaxParts.
    static std::size_t count_parts(const CmfLayout& layout);

    const CmfLayout& layout() const { return layout_; }
    std::span<const CmfPart> parts() const { return parts_; }
    std::size_t frame_count() const { return frame_count_; }
    // Bytes of EtherCAT payload (datagrams with their headers and WKCs) of the fullest frame.
    std::size_t max_frame_payload() const { return max_frame_payload_; }

private:
    CmfPlan(CmfLayout layout, std::vector<CmfPart> parts);

    CmfLayout layout_;
    std::vector<CmfPart> parts_;
    std::size_t frame_count_ = 0;
    std::size_t max_frame_payload_ = 0;
};

// ---- the HEADER section

struct CmfFlags {
    bool ring_broken = false;      // the ACTIVE sees a line break
    bool handoff_request = false;  // switchover: the ACTIVE hands the bus to its partner at CmfSender::handoff_cycle
    // With handoff_request: the ACTIVE has read the partner's acknowledgement and
    // steps down at the hand-off cycle whatever it hears from now on (irrevocable).
    bool handoff_committed = false;
    friend bool operator==(const CmfFlags&, const CmfFlags&) = default;
};

// Who sends a CMF and what it claims: read by the partner for arbitration
// (two ACTIVE masters), for a planned hand-off, and to lock its cycle to the
// sender's.
struct CmfSender {
    std::uint32_t epoch = 0;           // the sender's ACTIVE term (see arbitration/): higher = took the bus later
    std::uint64_t handoff_cycle = 0;   // with CmfFlags::handoff_request: the first cycle the partner sends
    std::uint16_t slaves_reached = 0;  // slaves that answered the sender's last complete cycle
    wire::MacAddress member;           // the sender's MAIN adapter: names it and breaks arbitration ties
    std::uint32_t send_offset_ns = 0;  // from the start of the sender's cycle to this CMF's send
    friend bool operator==(const CmfSender&, const CmfSender&) = default;
};

struct CmfHeader {
    static constexpr std::size_t kSize = 92;

    std::uint8_t format_version = kCmfFormatVersion;
    eni::SlaveState master_state = eni::SlaveState::Init;
    CmfFlags flags;
    std::uint64_t cycle = 0;
    std::uint16_t slave_count = 0;
    std::uint16_t part_count = 0;
    std::uint32_t slave_state_size = 0;
    std::uint32_t shadow_inputs_size = 0;
    std::uint32_t master_pd_out_size = 0;
    std::uint32_t master_pd_in_size = 0;
    PairParameters parameters;
    std::uint64_t fingerprint = 0;
    CmfSender sender;

    // The header the ACTIVE sends for a plan in a cycle.
    static CmfHeader describe(const CmfPlan& plan, std::uint64_t cycle, eni::SlaveState master_state, CmfFlags flags,
                              const CmfSender& sender);
    CmfLayout layout() const { return CmfLayout{parameters, slave_count, shadow_inputs_size}; }

    void encode(Bytes out) const;  // out.size() >= kSize
    // Checks the version, the master state, that the pair parameters use no
    // reserved bits, and that sizes, part count and fingerprint agree with
    // each other. `offset` is where `in` starts (for errors).
    static Expected<CmfHeader, CmfError> decode(ConstBytes in, std::size_t offset);

    friend bool operator==(const CmfHeader&, const CmfHeader&) = default;
};

// ---- the SLAVE_STATE_IMAGE section: one entry per ENI slave, in ENI order

inline constexpr std::size_t kCmfSlaveEntrySize = 6;
void encode_slave_entry(const master::SlaveStateEntry& entry, Bytes out);  // out.size() >= kCmfSlaveEntrySize
master::SlaveStateEntry decode_slave_entry(ConstBytes in);                 // in.size() >= kCmfSlaveEntrySize

// ---- the STANDBY_STATUS section: the INACTIVE tells the ACTIVE what kind of standby it is

struct CmfStandbyStatus {
    static constexpr std::size_t kSize = 16;

    bool hot = false;                    // mirrors this ACTIVE, fresh and with the same fingerprint: can take over hot
    bool forced = false;                 // forced to standby by its operator: never takes over
    bool partner_differs = false;        // its ENI or pair parameters differ from the ACTIVE's
    bool switchover_requested = false;   // its operator asks for a switchover
    bool handoff_acknowledged = false;   // takes over at handoff_cycle_low, as the ACTIVE announced
    bool main_link_up = false;
    bool red_link_up = false;
    wire::MacAddress member;             // its MAIN adapter
    std::uint32_t handoff_cycle_low = 0;
    std::uint32_t epoch = 0;             // the newest epoch it knows

    void encode(Bytes out) const;  // out.size() >= kSize
    static CmfStandbyStatus decode(ConstBytes in);  // in.size() >= kSize; reserved bits ignored
    friend bool operator==(const CmfStandbyStatus&, const CmfStandbyStatus&) = default;
};

// ---- the values one CMF carries

// Writer input; the assembler's output points into its own buffers.
struct CmfContent {
    std::uint64_t cycle = 0;
    eni::SlaveState master_state = eni::SlaveState::Init;
    CmfFlags flags;
    CmfSender sender;
    std::span<const master::SlaveStateEntry> slaves;
    ConstBytes shadow_inputs;  // the merged input image of the last cycle
    ConstBytes master_pd_out;  // ACTIVE -> INACTIVE
    // INACTIVE -> ACTIVE. Only meaningful when decoded: the writer reserves
    // these sections (zeros) and the INACTIVE writes them as it forwards the frame.
    ConstBytes master_pd_in;
    ConstBytes standby_status;  // CmfStandbyStatus::kSize bytes
};

}  // namespace ecpair::redundancy
