// The CMF wire format, version 2: segment header, HEADER section, slave
// entries, and the plan that cuts a layout into datagrams and frames.
//
// The plan is a greedy fill: sections in kind order, each poured into the
// current frame until the frame's 1498 bytes of EtherCAT payload cannot hold
// another datagram with at least one payload byte, then into the next frame.
// walk_parts() is that one algorithm; CmfPlan::make() records its output and
// CmfPlan::count_parts() only counts it (header validation must not allocate).

#include "ecpair/redundancy/cmf_format.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::redundancy {
namespace {

constexpr std::size_t kPartOverhead = wire::kDatagramOverhead + CmfSegmentHeader::kSize;

// Calls visit(part) for every part of the layout in wire order until it
// returns false.
template <class Visit>
void walk_parts(const CmfLayout& layout, Visit&& visit) {
    std::size_t room = wire::kMaxEcatPayload;
    std::uint16_t frame = 0;
    for (const CmfKind kind : kCmfKinds) {
        std::uint32_t left = layout.section_size(kind);
        std::uint32_t offset = 0;
        while (left > 0) {
            if (room < kPartOverhead + 1) {
                ++frame;
                room = wire::kMaxEcatPayload;
            }
            const auto length = static_cast<std::uint32_t>(std::min<std::size_t>(left, room - kPartOverhead));
            if (!visit(CmfPart{kind, frame, offset, length})) return;
            room -= kPartOverhead + length;
            left -= length;
            offset += length;
        }
    }
}

bool is_master_state(std::uint8_t value) {
    using eni::SlaveState;
    switch (static_cast<SlaveState>(value)) {
        case SlaveState::Init:
        case SlaveState::Preop:
        case SlaveState::Boot:
        case SlaveState::Safeop:
        case SlaveState::Op:
            return true;
    }
    return false;
}

bool cmf_datagram(wire::Command command, std::uint32_t address, ConstBytes data) {
    return command == wire::Command::Nop && address == wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo) &&
           data.size() >= CmfSegmentHeader::kMagic.size() && data[0] == CmfSegmentHeader::kMagic[0] &&
           data[1] == CmfSegmentHeader::kMagic[1];
}

constexpr std::uint16_t kRingBrokenBit = 0x0001;
constexpr std::uint16_t kHandoffRequestBit = 0x0002;
constexpr std::uint16_t kHandoffCommittedBit = 0x0004;
constexpr std::uint8_t kSlavePresentBit = 0x01;

}  // namespace

std::string_view to_string(CmfErrc code) {
    switch (code) {
        case CmfErrc::Truncated: return "Truncated";
        case CmfErrc::BadMagic: return "BadMagic";
        case CmfErrc::UnsupportedVersion: return "UnsupportedVersion";
        case CmfErrc::UnknownKind: return "UnknownKind";
        case CmfErrc::InvalidMasterState: return "InvalidMasterState";
        case CmfErrc::InconsistentHeader: return "InconsistentHeader";
        case CmfErrc::FingerprintCorrupt: return "FingerprintCorrupt";
        case CmfErrc::ReservedBitsSet: return "ReservedBitsSet";
        case CmfErrc::CycleMismatch: return "CycleMismatch";
        case CmfErrc::PartnerDiffers: return "PartnerDiffers";
        case CmfErrc::LayoutMismatch: return "LayoutMismatch";
        case CmfErrc::BadPlacement: return "BadPlacement";
    }
    return "Unknown";
}

std::string CmfError::describe() const {
    return fmt::format("CMF {} at frame offset {}: found {:#x}, expected {:#x}", to_string(code), offset, found,
                       expected);
}

// ---- segment header

void CmfSegmentHeader::encode(Bytes out) const {
    out[0] = kMagic[0];
    out[1] = kMagic[1];
    out[2] = version;
    out[3] = static_cast<std::uint8_t>(kind);
    store_le<std::uint16_t>(out, 4, part);
    store_le<std::uint16_t>(out, 6, part_count);
    store_le<std::uint32_t>(out, 8, offset);
    store_le<std::uint32_t>(out, 12, cycle_low);
}

Expected<CmfSegmentHeader, CmfError> CmfSegmentHeader::decode(ConstBytes data, std::size_t data_offset) {
    if (data.size() < kSize) return unexpected(CmfError{CmfErrc::Truncated, data_offset, data.size(), kSize});
    if (data[0] != kMagic[0] || data[1] != kMagic[1]) {
        return unexpected(CmfError{CmfErrc::BadMagic, data_offset, load_be16(data, 0), load_be16(kMagic, 0)});
    }
    CmfSegmentHeader h;
    h.version = data[2];
    if (h.version != kCmfFormatVersion) {
        return unexpected(CmfError{CmfErrc::UnsupportedVersion, data_offset + 2, h.version, kCmfFormatVersion});
    }
    const std::uint8_t kind = data[3];
    if (kind < static_cast<std::uint8_t>(CmfKind::Header) || kind > static_cast<std::uint8_t>(CmfKind::StandbyStatus)) {
        return unexpected(CmfError{CmfErrc::UnknownKind, data_offset + 3, kind, 0});
    }
    h.kind = static_cast<CmfKind>(kind);
    h.part = load_le<std::uint16_t>(data, 4);
    h.part_count = load_le<std::uint16_t>(data, 6);
    h.offset = load_le<std::uint32_t>(data, 8);
    h.cycle_low = load_le<std::uint32_t>(data, 12);
    if (h.part >= h.part_count) {
        return unexpected(CmfError{CmfErrc::BadPlacement, data_offset + 4, h.part, h.part_count});
    }
    return h;
}

bool is_cmf_datagram(const wire::ConstDatagramView& datagram) {
    return cmf_datagram(datagram.command(), datagram.address(), datagram.data());
}

bool is_cmf_datagram(const wire::DatagramView& datagram) {
    return cmf_datagram(datagram.command(), datagram.address(), datagram.data());
}

// ---- layout and plan

std::uint32_t CmfLayout::section_size(CmfKind kind) const {
    switch (kind) {
        case CmfKind::Header: return static_cast<std::uint32_t>(CmfHeader::kSize);
        case CmfKind::SlaveStateImage: return static_cast<std::uint32_t>(slave_count * kCmfSlaveEntrySize);
        case CmfKind::ShadowInputs: return shadow_inputs_size;
        case CmfKind::MasterPdOut: return parameters.master_pd_out_size;
        case CmfKind::MasterPdIn: return parameters.master_pd_in_size;
        case CmfKind::StandbyStatus: return static_cast<std::uint32_t>(CmfStandbyStatus::kSize);
    }
    return 0;
}

std::size_t CmfPlan::count_parts(const CmfLayout& layout) {
    std::size_t count = 0;
    walk_parts(layout, [&count](const CmfPart&) { return ++count <= kMaxParts; });
    return count;
}

Expected<CmfPlan, std::string> CmfPlan::make(const CmfLayout& layout) {
    const std::size_t count = count_parts(layout);
    if (count > kMaxParts) {
        return unexpected(fmt::format("the CMF would need more than {} datagrams ({} slaves, {} shadow input bytes, "
                                      "{} master PD out bytes, {} master PD in bytes)",
                                      kMaxParts, layout.slave_count, layout.shadow_inputs_size,
                                      layout.parameters.master_pd_out_size, layout.parameters.master_pd_in_size));
    }
    std::vector<CmfPart> parts;
    parts.reserve(count);
    walk_parts(layout, [&parts](const CmfPart& part) {
        parts.push_back(part);
        return true;
    });
    return CmfPlan(layout, std::move(parts));
}

CmfPlan::CmfPlan(CmfLayout layout, std::vector<CmfPart> parts) : layout_(layout), parts_(std::move(parts)) {
    std::size_t frame_payload = 0;
    for (std::size_t i = 0; i < parts_.size(); ++i) {
        if (i > 0 && parts_[i].frame != parts_[i - 1].frame) frame_payload = 0;
        frame_payload += kPartOverhead + parts_[i].length;
        max_frame_payload_ = std::max(max_frame_payload_, frame_payload);
    }
    frame_count_ = parts_.empty() ? 0 : parts_.back().frame + std::size_t{1};
}

// ---- HEADER
//
//  0 u8  format version     12 u16 slave count          28 u32 master PD in size
//  1 u8  master state       14 u16 part count           32 28B pair parameters
//  2 u16 flags              16 u32 slave state size     60 u64 fingerprint
//  4 u64 cycle counter      20 u32 shadow inputs size   68 u32 epoch
//                           24 u32 master PD out size   72 u64 hand-off cycle
//  80 u16 slaves reached    82 6B  sender's MAIN MAC    88 u32 send offset (ns)

CmfHeader CmfHeader::describe(const CmfPlan& plan, std::uint64_t cycle, eni::SlaveState master_state,
                              CmfFlags flags, const CmfSender& sender) {
    const CmfLayout& layout = plan.layout();
    CmfHeader h;
    h.master_state = master_state;
    h.flags = flags;
    h.cycle = cycle;
    h.slave_count = layout.slave_count;
    h.part_count = static_cast<std::uint16_t>(plan.parts().size());
    h.slave_state_size = layout.section_size(CmfKind::SlaveStateImage);
    h.shadow_inputs_size = layout.shadow_inputs_size;
    h.master_pd_out_size = layout.parameters.master_pd_out_size;
    h.master_pd_in_size = layout.parameters.master_pd_in_size;
    h.parameters = layout.parameters;
    h.fingerprint = layout.parameters.fingerprint();
    h.sender = sender;
    return h;
}

void CmfHeader::encode(Bytes out) const {
    out[0] = format_version;
    out[1] = static_cast<std::uint8_t>(master_state);
    store_le<std::uint16_t>(out, 2,
                            static_cast<std::uint16_t>((flags.ring_broken ? kRingBrokenBit : 0) |
                                                       (flags.handoff_request ? kHandoffRequestBit : 0) |
                                                       (flags.handoff_committed ? kHandoffCommittedBit : 0)));
    store_le<std::uint64_t>(out, 4, cycle);
    store_le<std::uint16_t>(out, 12, slave_count);
    store_le<std::uint16_t>(out, 14, part_count);
    store_le<std::uint32_t>(out, 16, slave_state_size);
    store_le<std::uint32_t>(out, 20, shadow_inputs_size);
    store_le<std::uint32_t>(out, 24, master_pd_out_size);
    store_le<std::uint32_t>(out, 28, master_pd_in_size);
    parameters.encode(out.subspan(32, PairParameters::kEncodedSize));
    store_le<std::uint64_t>(out, 60, fingerprint);
    store_le<std::uint32_t>(out, 68, sender.epoch);
    store_le<std::uint64_t>(out, 72, sender.handoff_cycle);
    store_le<std::uint16_t>(out, 80, sender.slaves_reached);
    std::copy(sender.member.bytes.begin(), sender.member.bytes.end(), out.begin() + 82);
    store_le<std::uint32_t>(out, 88, sender.send_offset_ns);
}

Expected<CmfHeader, CmfError> CmfHeader::decode(ConstBytes in, std::size_t offset) {
    if (in.size() < kSize) return unexpected(CmfError{CmfErrc::Truncated, offset, in.size(), kSize});
    CmfHeader h;
    h.format_version = in[0];
    if (h.format_version != kCmfFormatVersion) {
        return unexpected(CmfError{CmfErrc::UnsupportedVersion, offset, h.format_version, kCmfFormatVersion});
    }
    if (!is_master_state(in[1])) return unexpected(CmfError{CmfErrc::InvalidMasterState, offset + 1, in[1], 0});
    h.master_state = static_cast<eni::SlaveState>(in[1]);
    const auto flags = load_le<std::uint16_t>(in, 2);
    h.flags.ring_broken = (flags & kRingBrokenBit) != 0;
    h.flags.handoff_request = (flags & kHandoffRequestBit) != 0;
    h.flags.handoff_committed = (flags & kHandoffCommittedBit) != 0;
    h.cycle = load_le<std::uint64_t>(in, 4);
    h.slave_count = load_le<std::uint16_t>(in, 12);
    h.part_count = load_le<std::uint16_t>(in, 14);
    h.slave_state_size = load_le<std::uint32_t>(in, 16);
    h.shadow_inputs_size = load_le<std::uint32_t>(in, 20);
    h.master_pd_out_size = load_le<std::uint32_t>(in, 24);
    h.master_pd_in_size = load_le<std::uint32_t>(in, 28);
    const ConstBytes parameters = in.subspan(32, PairParameters::kEncodedSize);
    h.parameters = PairParameters::decode(parameters);
    h.fingerprint = load_le<std::uint64_t>(in, 60);
    h.sender.epoch = load_le<std::uint32_t>(in, 68);
    h.sender.handoff_cycle = load_le<std::uint64_t>(in, 72);
    h.sender.slaves_reached = load_le<std::uint16_t>(in, 80);
    std::copy_n(in.begin() + 82, h.sender.member.bytes.size(), h.sender.member.bytes.begin());
    h.sender.send_offset_ns = load_le<std::uint32_t>(in, 88);

    // Parameters must agree bit for bit; bits we cannot decode cannot agree.
    std::array<std::uint8_t, PairParameters::kEncodedSize> known{};
    h.parameters.encode(known);
    const auto differs = std::mismatch(known.begin(), known.end(), parameters.begin());
    if (differs.first != known.end()) {
        const auto at = static_cast<std::size_t>(differs.first - known.begin());
        return unexpected(CmfError{CmfErrc::ReservedBitsSet, offset + 32 + at, parameters[at], known[at]});
    }

    const std::uint64_t slave_state_size = std::uint64_t{h.slave_count} * kCmfSlaveEntrySize;
    if (h.slave_state_size != slave_state_size) {
        return unexpected(CmfError{CmfErrc::InconsistentHeader, offset + 16, h.slave_state_size, slave_state_size});
    }
    if (h.master_pd_out_size != h.parameters.master_pd_out_size) {
        return unexpected(CmfError{CmfErrc::InconsistentHeader, offset + 24, h.master_pd_out_size,
                                   h.parameters.master_pd_out_size});
    }
    if (h.master_pd_in_size != h.parameters.master_pd_in_size) {
        return unexpected(CmfError{CmfErrc::InconsistentHeader, offset + 28, h.master_pd_in_size,
                                   h.parameters.master_pd_in_size});
    }
    const std::uint64_t fingerprint = h.parameters.fingerprint();
    if (h.fingerprint != fingerprint) {
        return unexpected(CmfError{CmfErrc::FingerprintCorrupt, offset + 60, h.fingerprint, fingerprint});
    }
    const std::size_t parts = CmfPlan::count_parts(h.layout());
    if (h.part_count != parts) {
        return unexpected(CmfError{CmfErrc::InconsistentHeader, offset + 14, h.part_count, parts});
    }
    return h;
}

// ---- STANDBY_STATUS
//
//  0 u8  flags: b0 hot, b1 forced, b2 partner differs, b3 switchover requested,
//               b4 hand-off acknowledged, b5 MAIN link up, b6 RED link up
//  1 u8  reserved            2 6B  its MAIN MAC          8 u32 hand-off cycle (low 32 bits)
//                                                        12 u32 epoch

namespace {

constexpr std::uint8_t kStandbyHot = 0x01;
constexpr std::uint8_t kStandbyForced = 0x02;
constexpr std::uint8_t kStandbyPartnerDiffers = 0x04;
constexpr std::uint8_t kStandbySwitchoverRequested = 0x08;
constexpr std::uint8_t kStandbyHandoffAcknowledged = 0x10;
constexpr std::uint8_t kStandbyMainUp = 0x20;
constexpr std::uint8_t kStandbyRedUp = 0x40;

std::uint8_t bit_if(bool on, std::uint8_t bit) { return on ? bit : std::uint8_t{0}; }

}  // namespace

void CmfStandbyStatus::encode(Bytes out) const {
    out[0] = static_cast<std::uint8_t>(bit_if(hot, kStandbyHot) | bit_if(forced, kStandbyForced) |
                                       bit_if(partner_differs, kStandbyPartnerDiffers) |
                                       bit_if(switchover_requested, kStandbySwitchoverRequested) |
                                       bit_if(handoff_acknowledged, kStandbyHandoffAcknowledged) |
                                       bit_if(main_link_up, kStandbyMainUp) | bit_if(red_link_up, kStandbyRedUp));
    out[1] = 0;
    std::copy(member.bytes.begin(), member.bytes.end(), out.begin() + 2);
    store_le<std::uint32_t>(out, 8, handoff_cycle_low);
    store_le<std::uint32_t>(out, 12, epoch);
}

CmfStandbyStatus CmfStandbyStatus::decode(ConstBytes in) {
    CmfStandbyStatus s;
    const std::uint8_t flags = in[0];
    s.hot = (flags & kStandbyHot) != 0;
    s.forced = (flags & kStandbyForced) != 0;
    s.partner_differs = (flags & kStandbyPartnerDiffers) != 0;
    s.switchover_requested = (flags & kStandbySwitchoverRequested) != 0;
    s.handoff_acknowledged = (flags & kStandbyHandoffAcknowledged) != 0;
    s.main_link_up = (flags & kStandbyMainUp) != 0;
    s.red_link_up = (flags & kStandbyRedUp) != 0;
    std::copy_n(in.begin() + 2, s.member.bytes.size(), s.member.bytes.begin());
    s.handoff_cycle_low = load_le<std::uint32_t>(in, 8);
    s.epoch = load_le<std::uint32_t>(in, 12);
    return s;
}

// ---- slave entries
//
//  0 u8  flags: b0 present,     2 u16 station address
//        b1-b4 Hot-Connect      4 u16 AL status code (0x0134)
//  1 u8  AL status (0x0130)
// The Hot-Connect bits are SlaveStateEntry::hot_connect shifted up by one
// (group present, joining, awaiting accept, refused); b5-b7 reserved.

void encode_slave_entry(const master::SlaveStateEntry& entry, Bytes out) {
    out[0] = static_cast<std::uint8_t>((entry.present ? kSlavePresentBit : 0) |
                                       ((entry.hot_connect & master::kHotConnectFlags) << 1));
    out[1] = entry.al_status;
    store_le<std::uint16_t>(out, 2, entry.station_address);
    store_le<std::uint16_t>(out, 4, entry.al_status_code);
}

master::SlaveStateEntry decode_slave_entry(ConstBytes in) {
    master::SlaveStateEntry entry;
    entry.present = (in[0] & kSlavePresentBit) != 0;
    entry.hot_connect = static_cast<std::uint8_t>((in[0] >> 1) & master::kHotConnectFlags);
    entry.al_status = in[1];
    entry.station_address = load_le<std::uint16_t>(in, 2);
    entry.al_status_code = load_le<std::uint16_t>(in, 4);
    return entry;
}

}  // namespace ecpair::redundancy
