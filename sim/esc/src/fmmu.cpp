// The bit path walks the mapped bits that fall inside the datagram one
// physical byte at a time: it reads (or read-modify-writes) that byte once and
// moves the bits between it and the datagram.

#include "fmmu.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

bool ranges_overlap(std::uint64_t begin, std::uint64_t end, std::uint64_t other_begin, std::uint64_t other_end) {
    return begin < other_end && other_begin < end;
}

std::uint8_t bit_of(ConstBytes bytes, std::uint64_t bit) {
    return static_cast<std::uint8_t>((unsigned{bytes[static_cast<std::size_t>(bit / 8)]} >> (bit % 8)) & 1U);
}

void set_bit(Bytes bytes, std::uint64_t bit, std::uint8_t value) {
    auto& byte = bytes[static_cast<std::size_t>(bit / 8)];
    const auto mask = static_cast<std::uint8_t>(1U << (bit % 8));
    byte = static_cast<std::uint8_t>(value != 0 ? (byte | mask) : (byte & ~mask));
}

}  // namespace

void FmmuUnit::refresh(const EscMemory& memory) {
    count_ = 0;
    for (std::size_t f = 0; f < static_cast<std::size_t>(regs::kFmmuCount); ++f) {
        const auto config = wire::FmmuConfig::decode(memory.bytes().subspan(reg::kFmmuBase + f * reg::kFmmuSize, reg::kFmmuSize));
        if (!config.active || config.length == 0 || !(config.read || config.write)) continue;
        Mapping m;
        m.logical_bit_begin = std::uint64_t{config.logical_start} * 8 + config.logical_start_bit;
        m.logical_bit_end = (std::uint64_t{config.logical_start} + config.length - 1) * 8 + config.logical_stop_bit + 1;
        if (m.logical_bit_end <= m.logical_bit_begin) continue;  // stop bit before start bit in a 1-byte mapping
        m.physical_bit_begin = std::uint32_t{config.physical_start} * 8 + config.physical_start_bit;
        m.logical_byte_begin = config.logical_start;
        m.logical_byte_end = std::uint64_t{config.logical_start} + config.length;
        m.reads = config.read;
        m.writes = config.write;
        m.byte_aligned = config.logical_start_bit == 0 && config.logical_stop_bit == 7 && config.physical_start_bit == 0;
        for (std::size_t lower = 0; lower < count_; ++lower) {
            const Mapping& other = mappings_[lower];
            if (!ranges_overlap(m.logical_byte_begin, m.logical_byte_end, other.logical_byte_begin, other.logical_byte_end)) continue;
            m.shadowed_read = m.shadowed_read || (m.reads && other.reads);
            m.shadowed_write = m.shadowed_write || (m.writes && other.writes);
        }
        mappings_[count_++] = m;
    }
}

bool FmmuUnit::maps(std::uint32_t logical_address, std::size_t length) const {
    const std::uint64_t end = std::uint64_t{logical_address} + length;
    for (std::size_t i = 0; i < count_; ++i) {
        const Mapping& m = mappings_[i];
        if (ranges_overlap(logical_address, end, m.logical_byte_begin, m.logical_byte_end)) return true;
    }
    return false;
}

namespace {

// Where a byte-aligned mapping puts the part of the datagram [begin, end) it covers.
struct AlignedPiece {
    std::uint64_t physical;  // first physical byte
    std::size_t offset;      // in the datagram's data
    std::size_t length;
};

template <class Mapping>
AlignedPiece aligned_piece(const Mapping& m, std::uint64_t begin, std::uint64_t end) {
    const std::uint64_t overlap_begin = std::max<std::uint64_t>(begin, m.logical_byte_begin);
    const std::uint64_t overlap_end = std::min(end, m.logical_byte_end);
    return {m.physical_bit_begin / 8 + (overlap_begin - m.logical_byte_begin),
            static_cast<std::size_t>(overlap_begin - begin), static_cast<std::size_t>(overlap_end - overlap_begin)};
}

// The bits of a bit-granular mapping a datagram at `logical_address` of
// `size` bytes covers, as [first, last) relative to the mapping's first bit.
struct BitWindow {
    std::uint64_t datagram_bit_begin;  // absolute bit number of the datagram's first bit
    std::uint64_t first;
    std::uint64_t last;
};

template <class Mapping>
BitWindow bit_window(const Mapping& m, std::uint32_t logical_address, std::size_t size) {
    const std::uint64_t datagram_bit_begin = std::uint64_t{logical_address} * 8;
    const std::uint64_t datagram_bit_end = datagram_bit_begin + std::uint64_t{size} * 8;
    return {datagram_bit_begin, std::max(m.logical_bit_begin, datagram_bit_begin) - m.logical_bit_begin,
            std::min(m.logical_bit_end, datagram_bit_end) - m.logical_bit_begin};
}

}  // namespace

bool FmmuUnit::read(std::uint32_t logical_address, Bytes data, PhysicalAccess& memory) const {
    const std::uint64_t begin = logical_address;
    const std::uint64_t end = begin + data.size();
    bool any = false;
    for (std::size_t i = 0; i < count_; ++i) {
        const Mapping& m = mappings_[i];
        if (!m.reads || !ranges_overlap(m.logical_byte_begin, m.logical_byte_end, begin, end)) continue;
        if (m.byte_aligned && !m.shadowed_read) {
            const auto piece = aligned_piece(m, begin, end);
            any = (piece.physical < regs::kAddressSpace &&
                   memory.read(static_cast<std::uint32_t>(piece.physical), data.subspan(piece.offset, piece.length),
                               ReadMode::Copy)) ||
                  any;
        } else {
            any = read_bits(i, logical_address, data, memory) || any;
        }
    }
    return any;
}

bool FmmuUnit::write(std::uint32_t logical_address, ConstBytes source, PhysicalAccess& memory) const {
    const std::uint64_t begin = logical_address;
    const std::uint64_t end = begin + source.size();
    bool any = false;
    for (std::size_t i = 0; i < count_; ++i) {
        const Mapping& m = mappings_[i];
        if (!m.writes || !ranges_overlap(m.logical_byte_begin, m.logical_byte_end, begin, end)) continue;
        if (m.byte_aligned && !m.shadowed_write) {
            const auto piece = aligned_piece(m, begin, end);
            any = (piece.physical < regs::kAddressSpace &&
                   memory.write(static_cast<std::uint32_t>(piece.physical), source.subspan(piece.offset, piece.length))) ||
                  any;
        } else {
            any = write_bits(i, logical_address, source, memory) || any;
        }
    }
    return any;
}

FmmuUnit::Window FmmuUnit::write_window(std::uint32_t logical_address, std::size_t length) const {
    const std::uint64_t begin = logical_address;
    const std::uint64_t end = begin + length;
    std::uint64_t low = end;
    std::uint64_t high = begin;
    for (std::size_t i = 0; i < count_; ++i) {
        const Mapping& m = mappings_[i];
        if (!m.writes || !ranges_overlap(m.logical_byte_begin, m.logical_byte_end, begin, end)) continue;
        low = std::min(low, std::max<std::uint64_t>(begin, m.logical_byte_begin));
        high = std::max(high, std::min(end, m.logical_byte_end));
    }
    if (low >= high) return {};
    return {static_cast<std::size_t>(low - begin), static_cast<std::size_t>(high - begin)};
}

bool FmmuUnit::claimed_by_lower(std::size_t index, std::uint64_t logical_byte, bool for_write) const {
    for (std::size_t lower = 0; lower < index; ++lower) {
        const Mapping& other = mappings_[lower];
        if ((for_write ? other.writes : other.reads) && other.logical_byte_begin <= logical_byte &&
            logical_byte < other.logical_byte_end) {
            return true;
        }
    }
    return false;
}

bool FmmuUnit::read_bits(std::size_t index, std::uint32_t logical_address, Bytes data, PhysicalAccess& memory) const {
    const Mapping& m = mappings_[index];
    const auto [datagram_bit_begin, first, last] = bit_window(m, logical_address, data.size());
    bool any = false;
    for (std::uint64_t k = first; k < last;) {
        const std::uint64_t physical_bit = m.physical_bit_begin + k;
        const std::uint64_t physical_byte = physical_bit / 8;
        const auto shift = static_cast<unsigned>(physical_bit % 8);
        const std::uint64_t run = std::min<std::uint64_t>(last - k, 8 - shift);
        std::uint8_t eligible = 0;  // bits of the physical byte this FMMU may move
        for (std::uint64_t j = 0; j < run; ++j) {
            const std::uint64_t logical_byte = (m.logical_bit_begin + k + j) / 8;
            if (!m.shadowed_read || !claimed_by_lower(index, logical_byte, false)) {
                eligible = static_cast<std::uint8_t>(eligible | (1U << (shift + j)));
            }
        }
        std::uint8_t value = 0;
        if (eligible != 0 && physical_byte < regs::kAddressSpace &&
            memory.read(static_cast<std::uint32_t>(physical_byte), Bytes(&value, 1), ReadMode::Copy)) {
            any = true;
            for (std::uint64_t j = 0; j < run; ++j) {
                if ((eligible & (1U << (shift + j))) == 0) continue;
                const std::uint64_t datagram_bit = m.logical_bit_begin + k + j - datagram_bit_begin;
                set_bit(data, datagram_bit, static_cast<std::uint8_t>((unsigned{value} >> (shift + j)) & 1U));
            }
        }
        k += run;
    }
    return any;
}

bool FmmuUnit::write_bits(std::size_t index, std::uint32_t logical_address, ConstBytes source,
                          PhysicalAccess& memory) const {
    const Mapping& m = mappings_[index];
    const auto [datagram_bit_begin, first, last] = bit_window(m, logical_address, source.size());
    bool any = false;
    for (std::uint64_t k = first; k < last;) {
        const std::uint64_t physical_bit = m.physical_bit_begin + k;
        const std::uint64_t physical_byte = physical_bit / 8;
        const auto shift = static_cast<unsigned>(physical_bit % 8);
        const std::uint64_t run = std::min<std::uint64_t>(last - k, 8 - shift);
        if (physical_byte >= regs::kAddressSpace) break;
        const auto address = static_cast<std::uint16_t>(physical_byte);
        std::uint8_t value = memory.pending_value(address);
        bool touched = false;
        for (std::uint64_t j = 0; j < run; ++j) {
            const std::uint64_t logical_bit = m.logical_bit_begin + k + j;
            if (m.shadowed_write && claimed_by_lower(index, logical_bit / 8, true)) continue;
            const auto mask = static_cast<std::uint8_t>(1U << (shift + j));
            const bool one = bit_of(source, logical_bit - datagram_bit_begin) != 0;
            value = static_cast<std::uint8_t>(one ? (value | mask) : (value & ~mask));
            touched = true;
        }
        if (touched && memory.write(address, ConstBytes(&value, 1))) any = true;
        k += run;
    }
    return any;
}

}  // namespace ecpair::sim
