// CmfAssembler: checks every CMF datagram against the plan we expect and
// copies its payload into the sections of the cycle being assembled.
//
//   datagram --address--> NotCmf
//            --segment header (size, magic, version, kind, part)--> error
//            --HEADER only: decode, remember as last_header(), compare
//              fingerprint and layout with ours--> error
//            --part count, kind, offset and length as the plan says--> error
//            --cycle: same / newer / stale / restarted--> place the payload
//
// Two buffers: parts go into `assembling_`; when the last one is in, the
// slave entries are decoded and the buffers swap, so content() stays valid
// while the next cycle arrives. Both are sized from the plan once.

#include "ecpair/redundancy/cmf_assembler.hpp"

#include <algorithm>
#include <utility>

#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::redundancy {
namespace {

std::size_t index_of(CmfKind kind) { return static_cast<std::size_t>(kind); }

}  // namespace

CmfAssembler::CmfAssembler(CmfPlan expected) : plan_(std::move(expected)) {
    std::size_t offset = 0;
    for (const CmfKind kind : kCmfKinds) {
        section_offset_[index_of(kind)] = offset;
        offset += plan_.layout().section_size(kind);
    }
    for (CycleBuffers* buffers : {&assembling_, &complete_}) {
        buffers->sections.resize(offset);
        buffers->slaves.resize(plan_.layout().slave_count);
    }
    received_.resize(plan_.parts().size());
}

Expected<CmfAssembler::Outcome, CmfError> CmfAssembler::feed(const wire::ConstDatagramView& datagram) {
    // The address alone decides whether a datagram is ours to judge: at the
    // CMF address, a wrong magic is an error, not someone else's datagram.
    if (datagram.command() != wire::Command::Nop ||
        datagram.address() != wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo)) {
        return Outcome::NotCmf;
    }
    const ConstBytes data = datagram.data();
    const std::size_t data_offset = datagram.frame_offset() + wire::kDatagramHeaderSize;
    const auto segment = CmfSegmentHeader::decode(data, data_offset);
    if (!segment) return fail(segment.error());
    const ConstBytes payload = data.subspan(CmfSegmentHeader::kSize);
    if (segment->kind == CmfKind::Header) {
        if (auto ok = check_header(*segment, payload, data_offset + CmfSegmentHeader::kSize); !ok) {
            return fail(ok.error());
        }
    }
    if (auto ok = check_placement(*segment, payload.size(), data_offset); !ok) return fail(ok.error());
    return place(*segment, payload, datagram.wkc());
}

Expected<void, CmfError> CmfAssembler::check_header(const CmfSegmentHeader& segment, ConstBytes payload,
                                                    std::size_t payload_offset) {
    auto header = CmfHeader::decode(payload, payload_offset);
    if (!header) return unexpected(header.error());
    last_header_ = *header;
    if (header->part_count != segment.part_count) {
        return unexpected(
            CmfError{CmfErrc::InconsistentHeader, payload_offset + 14, header->part_count, segment.part_count});
    }
    if (static_cast<std::uint32_t>(header->cycle) != segment.cycle_low) {
        return unexpected(CmfError{CmfErrc::CycleMismatch, payload_offset + 4, header->cycle, segment.cycle_low});
    }
    const CmfLayout& ours = plan_.layout();
    const std::uint64_t our_fingerprint = ours.parameters.fingerprint();
    if (header->fingerprint != our_fingerprint) {
        return unexpected(CmfError{CmfErrc::PartnerDiffers, payload_offset + 60, header->fingerprint, our_fingerprint});
    }
    if (header->slave_count != ours.slave_count) {
        return unexpected(CmfError{CmfErrc::LayoutMismatch, payload_offset + 12, header->slave_count, ours.slave_count});
    }
    if (header->shadow_inputs_size != ours.shadow_inputs_size) {
        return unexpected(CmfError{CmfErrc::LayoutMismatch, payload_offset + 20, header->shadow_inputs_size,
                                   ours.shadow_inputs_size});
    }
    return {};
}

Expected<void, CmfError> CmfAssembler::check_placement(const CmfSegmentHeader& segment, std::size_t payload_length,
                                                       std::size_t data_offset) const {
    const auto parts = plan_.parts();
    if (segment.part_count != parts.size()) {
        return unexpected(CmfError{CmfErrc::LayoutMismatch, data_offset + 6, segment.part_count, parts.size()});
    }
    const CmfPart& expected = parts[segment.part];
    if (segment.kind != expected.kind) {
        return unexpected(CmfError{CmfErrc::BadPlacement, data_offset + 3, static_cast<std::uint64_t>(segment.kind),
                                   static_cast<std::uint64_t>(expected.kind)});
    }
    if (segment.offset != expected.offset) {
        return unexpected(CmfError{CmfErrc::BadPlacement, data_offset + 8, segment.offset, expected.offset});
    }
    if (payload_length != expected.length) {
        return unexpected(CmfError{CmfErrc::BadPlacement, data_offset - wire::kDatagramHeaderSize + 6,
                                   payload_length, expected.length});
    }
    return {};
}

CmfAssembler::Outcome CmfAssembler::place(const CmfSegmentHeader& segment, ConstBytes payload, std::uint16_t wkc) {
    if (cycle_low_ && segment.cycle_low == *cycle_low_) {
        if (cycle_done_ || received_[segment.part] != 0) {
            ++counters_.duplicates;
            return Outcome::Duplicate;
        }
    } else {
        if (cycle_low_) {
            const auto age = static_cast<std::int32_t>(*cycle_low_ - segment.cycle_low);
            if (age > 0 && age <= kStaleWindow) {
                ++counters_.stale;
                return Outcome::Stale;
            }
        }
        begin_cycle(segment.cycle_low);
    }

    const std::size_t at = section_offset_[index_of(segment.kind)] + segment.offset;
    std::copy(payload.begin(), payload.end(), assembling_.sections.begin() + static_cast<std::ptrdiff_t>(at));
    if (segment.kind == CmfKind::Header) assembling_.header = *last_header_;
    WorkingCounters& lowest = assembling_.wkc;
    if (segment.kind == CmfKind::MasterPdIn || segment.kind == CmfKind::StandbyStatus) {
        lowest.lowest_write = std::min(lowest.lowest_write.value_or(wkc), wkc);
    } else {
        lowest.lowest_read = std::min(lowest.lowest_read, wkc);
    }
    received_[segment.part] = 1;
    if (++received_count_ < received_.size()) return Outcome::Stored;
    finish_cycle();
    return Outcome::Completed;
}

void CmfAssembler::begin_cycle(std::uint32_t cycle_low) {
    if (cycle_low_ && !cycle_done_ && received_count_ > 0) ++counters_.abandoned;
    cycle_low_ = cycle_low;
    cycle_done_ = false;
    std::fill(received_.begin(), received_.end(), std::uint8_t{0});
    received_count_ = 0;
    assembling_.wkc = WorkingCounters{0xFFFF, std::nullopt};
}

void CmfAssembler::finish_cycle() {
    const ConstBytes slaves = section(assembling_, CmfKind::SlaveStateImage);
    for (std::size_t i = 0; i < assembling_.slaves.size(); ++i) {
        assembling_.slaves[i] = decode_slave_entry(slaves.subspan(i * kCmfSlaveEntrySize));
    }
    std::swap(assembling_, complete_);
    cycle_done_ = true;
    has_complete_ = true;
    ++counters_.completed;

    const CmfHeader& h = complete_.header;
    content_ = CmfContent{h.cycle,
                          h.master_state,
                          h.flags,
                          h.sender,
                          complete_.slaves,
                          section(complete_, CmfKind::ShadowInputs),
                          section(complete_, CmfKind::MasterPdOut),
                          section(complete_, CmfKind::MasterPdIn),
                          section(complete_, CmfKind::StandbyStatus)};
}

ConstBytes CmfAssembler::section(const CycleBuffers& buffers, CmfKind kind) const {
    return ConstBytes(buffers.sections).subspan(section_offset_[index_of(kind)], plan_.layout().section_size(kind));
}

Expected<CmfAssembler::Outcome, CmfError> CmfAssembler::fail(const CmfError& error) {
    ++counters_.errors;
    return unexpected(error);
}

}  // namespace ecpair::redundancy
