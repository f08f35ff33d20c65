#include "frame_addressing.hpp"

#include "ecpair/wire/command.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim::detail {
namespace {

bool overlaps(std::uint64_t begin, std::uint64_t end, std::uint64_t other_begin, std::uint64_t other_end) {
    return begin < other_end && other_begin < end;
}

// A physical write that may reach DL control or the DC receive-time latch.
// The read-write commands write to ADO + the slave's read/write offset (0x0108), which may be anything.
bool may_write_arrival_registers(const wire::DatagramView& datagram) {
    using wire::Command;
    namespace reg = wire::reg;
    switch (datagram.command()) {
        case Command::Aprw:
        case Command::Fprw:
        case Command::Brw: return true;
        case Command::Apwr:
        case Command::Fpwr:
        case Command::Bwr:
        case Command::Armw:
        case Command::Frmw: {
            const std::uint64_t ado = datagram.address() >> 16;
            const std::uint64_t end = ado + datagram.data().size();
            return overlaps(ado, end, reg::kDlControl, reg::kDlControl + 4) ||
                   overlaps(ado, end, reg::kDcReceiveTimes, reg::kDcReceiveTimes + 4);
        }
        default: return false;
    }
}

}  // namespace

bool FrameAddressing::summarise(const wire::FrameView& frame) {
    using wire::Command;
    auto_increment_count_ = configured_count_ = logical_count_ = 0;
    every_ = false;
    writes_arrival_registers_ = writes_logically_ = false;
    forget_passed();
    for (const auto datagram : frame) {
        writes_arrival_registers_ = writes_arrival_registers_ || may_write_arrival_registers(datagram);
        writes_logically_ = writes_logically_ || datagram.command() == wire::Command::Lwr ||
                            datagram.command() == wire::Command::Lrw;
        const auto adp = static_cast<std::uint16_t>(datagram.address() & 0xFFFF);
        switch (datagram.command()) {
            case Command::Aprd:
            case Command::Apwr:
            case Command::Aprw:
                if (auto_increment_count_ == kKept) return false;
                auto_increment_[auto_increment_count_++] = adp;
                break;
            case Command::Fprd:
            case Command::Fpwr:
            case Command::Fprw:
                if (configured_count_ == kKept) return false;
                configured_[configured_count_++] = adp;
                break;
            case Command::Lrd:
            case Command::Lwr:
            case Command::Lrw: {
                if (logical_count_ == kKept) return false;
                const std::uint64_t begin = datagram.address();
                logical_[logical_count_++] = {begin, begin + datagram.data().size()};
                break;
            }
            case Command::Brd:
            case Command::Bwr:
            case Command::Brw:
            case Command::Armw:
            case Command::Frmw: every_ = true; break;
            case Command::Nop:
            default: break;  // addresses no slave
        }
    }
    return true;
}

bool FrameAddressing::addresses(const PassDigest& digest, std::uint32_t epu_pass) const {
    if (every_) return true;
    for (std::size_t i = 0; i < auto_increment_count_; ++i) {
        if (static_cast<std::uint16_t>(auto_increment_[i] + epu_pass) == 0) return true;
    }
    for (std::size_t i = 0; i < configured_count_; ++i) {
        if (configured_[i] == digest.station_address || configured_[i] == digest.station_alias) return true;
    }
    for (std::size_t i = 0; i < logical_count_; ++i) {
        for (std::size_t r = 0; r < digest.logical_count; ++r) {
            const auto& range = digest.logical[r];
            if (overlaps(logical_[i].begin, logical_[i].end, range.begin, range.end)) return true;
        }
    }
    return false;
}

void FrameAddressing::set_auto_increment(wire::FrameView& frame, std::uint32_t epus) const {
    using wire::Command;
    if (auto_increment_count_ == 0) return;
    std::size_t i = 0;
    for (auto datagram : frame) {
        const Command command = datagram.command();
        if (command != Command::Aprd && command != Command::Apwr && command != Command::Aprw) continue;
        const auto adp = static_cast<std::uint16_t>(auto_increment_[i++] + epus);
        datagram.set_address((datagram.address() & 0xFFFF0000U) | adp);
    }
}

void FrameAddressing::apply_passed(wire::FrameView& frame) const {
    if (passed_irq_ != 0) {
        for (auto datagram : frame) datagram.set_irq(static_cast<std::uint16_t>(datagram.irq() | passed_irq_));
    }
    if (passed_forwarding_bit_ && (frame.ethernet().source.bytes[0] & 0x02) == 0) {
        wire::MacAddress source = frame.ethernet().source;
        source.bytes[0] = static_cast<std::uint8_t>(source.bytes[0] | 0x02);
        frame.set_source(source);
    }
}

}  // namespace ecpair::sim::detail
