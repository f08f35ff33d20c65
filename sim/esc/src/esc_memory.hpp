#pragma once
// The 64 KiB address space of one ESC: registers (0x0000-0x0F7F), user RAM
// (0x0F80-0x0FFF) and process RAM (from 0x1000, as large as 0x0006 says),
// plus the shadow buffer that holds the master's register writes until the
// frame ends (esc-facts.md §1, datasheet I §3.4).
//
// The bytes array is the effective state: what the master reads and what the
// PDI side (slave stack, application, tests) reads and writes directly.
// ECAT register writes go through stage(); commit_staged() applies them
// through the register write masks at the end of the frame, after which the
// owners of the touched registers ask staged_any() what changed and react,
// and clear_staged() forgets the frame. Nothing here allocates after
// construction.

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecpair/common/bytes.hpp"
#include "register_map.hpp"

namespace ecpair::sim {

class EscMemory {
public:
    EscMemory();

    // ---- direct (PDI-side) access to the effective state
    Bytes bytes() { return bytes_; }
    ConstBytes bytes() const { return bytes_; }
    std::uint8_t u8(std::uint16_t address) const { return bytes_[address]; }
    template <class T>
    T load(std::uint16_t address) const {
        return load_le<T>(ConstBytes(bytes_), address);
    }
    void set_u8(std::uint16_t address, std::uint8_t value) { bytes_[address] = value; }
    template <class T>
    void store(std::uint16_t address, T value) {
        store_le<T>(Bytes(bytes_), address, value);
    }
    void clear();

    // ---- process RAM: [0x1000, ram_end())
    void set_ram_bytes(std::size_t ram_bytes) { ram_end_ = static_cast<std::uint32_t>(regs::kProcessRam + ram_bytes); }
    std::uint32_t ram_end() const { return ram_end_; }

    // ---- shadowed ECAT register writes
    // Stages `data` at `address` (the range must lie below 0x0F80).
    void stage(std::uint16_t address, ConstBytes data);
    bool has_staged() const { return staged_begin_ < staged_end_; }
    bool staged(std::uint16_t address) const;
    std::uint8_t staged_value(std::uint16_t address) const { return shadow_[address]; }
    // Whether any byte of [begin, end) was staged in this frame.
    bool staged_any(std::uint16_t begin, std::uint16_t end) const;
    // The value a read-modify-write in this frame should start from: the
    // staged byte when there is one, the effective byte otherwise.
    std::uint8_t pending_value(std::uint16_t address) const;
    // Drops staged bytes of [begin, end) (writes the ESC refuses as a whole).
    void discard_staged(std::uint16_t begin, std::uint16_t end);
    // Applies the staged bytes through the ECAT write masks.
    void commit_staged();
    void clear_staged();

private:
    static constexpr std::size_t kWords = (regs::kShadowedEnd + 63) / 64;

    std::array<std::uint8_t, regs::kAddressSpace> bytes_{};
    std::array<std::uint8_t, regs::kShadowedEnd> shadow_{};
    std::array<std::uint64_t, kWords> staged_bits_{};
    std::uint16_t staged_begin_ = regs::kShadowedEnd;  // staged range, [begin, end)
    std::uint16_t staged_end_ = 0;
    std::uint32_t ram_end_ = regs::kProcessRam;
};

}  // namespace ecpair::sim
