// Staged bytes are tracked in a bitmap plus the [begin, end) range they lie
// in, so the end-of-frame work is bounded by what the frame actually wrote
// (usually nothing, or a few bytes).

#include "esc_memory.hpp"

#include <algorithm>
#include <cassert>

namespace ecpair::sim {

EscMemory::EscMemory() = default;

void EscMemory::clear() {
    bytes_.fill(0);
    clear_staged();
}

void EscMemory::stage(std::uint16_t address, ConstBytes data) {
    assert(address + data.size() <= regs::kShadowedEnd);
    if (data.empty()) return;
    std::copy(data.begin(), data.end(), shadow_.begin() + address);
    const auto end = static_cast<std::uint16_t>(address + data.size());
    for (std::uint16_t a = address; a < end; ++a) staged_bits_[a / 64] |= std::uint64_t{1} << (a % 64);
    staged_begin_ = std::min(staged_begin_, address);
    staged_end_ = std::max(staged_end_, end);
}

bool EscMemory::staged(std::uint16_t address) const {
    if (address >= regs::kShadowedEnd) return false;
    return (staged_bits_[address / 64] >> (address % 64)) & 1U;
}

bool EscMemory::staged_any(std::uint16_t begin, std::uint16_t end) const {
    begin = std::max(begin, staged_begin_);
    end = std::min(end, staged_end_);
    for (std::uint16_t a = begin; a < end; ++a) {
        if (staged(a)) return true;
    }
    return false;
}

std::uint8_t EscMemory::pending_value(std::uint16_t address) const {
    return staged(address) ? shadow_[address] : bytes_[address];
}

void EscMemory::discard_staged(std::uint16_t begin, std::uint16_t end) {
    for (std::uint16_t a = std::max(begin, staged_begin_); a < std::min(end, staged_end_); ++a) {
        staged_bits_[a / 64] &= ~(std::uint64_t{1} << (a % 64));
    }
}

void EscMemory::commit_staged() {
    for (std::uint16_t a = staged_begin_; a < staged_end_; ++a) {
        if (!staged(a)) continue;
        const std::uint8_t mask = regs::ecat_write_mask(a);
        bytes_[a] = static_cast<std::uint8_t>((bytes_[a] & ~mask) | (shadow_[a] & mask));
    }
}

void EscMemory::clear_staged() {
    if (!has_staged()) return;
    for (std::size_t w = staged_begin_ / 64; w <= (staged_end_ - 1U) / 64; ++w) staged_bits_[w] = 0;
    staged_begin_ = regs::kShadowedEnd;
    staged_end_ = 0;
}

}  // namespace ecpair::sim
