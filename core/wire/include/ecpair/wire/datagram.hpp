#pragma once
// One EtherCAT datagram: a 10-byte header, Len data bytes, a 2-byte working
// counter (esc-facts.md §1). DatagramHeader is the decoded header as a value;
// DatagramView is a window onto one datagram inside a frame buffer, so that a
// slave (ecsim) or a merge can change data and WKC in place.

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/command.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::wire {

struct DatagramHeader {
    Command command = Command::Nop;
    std::uint8_t index = 0;
    // ADP in bits 0-15 and ADO in bits 16-31, or the 32-bit logical address.
    std::uint32_t address = 0;
    std::uint16_t length = 0;  // 11 bits
    std::uint8_t reserved = 0; // the 3 reserved bits R[13:11], kept for round trips
    bool circulating = false;
    bool more = false;
    std::uint16_t irq = 0;

    static constexpr std::uint32_t physical(std::uint16_t adp, std::uint16_t ado) {
        return static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16);
    }
    std::uint16_t adp() const { return static_cast<std::uint16_t>(address & 0xFFFF); }
    std::uint16_t ado() const { return static_cast<std::uint16_t>(address >> 16); }
    void set_adp(std::uint16_t adp) { address = physical(adp, ado()); }

    // out/in must hold at least kDatagramHeaderSize bytes.
    void encode(Bytes out) const;
    static DatagramHeader decode(ConstBytes in);

    friend bool operator==(const DatagramHeader&, const DatagramHeader&) = default;
};

// A view of [header | data | wkc] inside a frame buffer. Byte is uint8_t for a
// mutable view, const uint8_t for a read-only one. The view never outlives the
// buffer and never changes the datagram's length.
template <class Byte>
class BasicDatagramView {
    static constexpr bool kMutable = !std::is_const_v<Byte>;

public:
    BasicDatagramView(std::span<Byte> bytes, std::size_t frame_offset)
        : bytes_(bytes), frame_offset_(frame_offset) {}

    DatagramHeader header() const { return DatagramHeader::decode(bytes_); }
    Command command() const { return static_cast<Command>(bytes_[0]); }
    std::uint8_t index() const { return bytes_[1]; }
    std::uint32_t address() const { return load_le<std::uint32_t>(bytes_, 2); }
    std::uint16_t length() const { return static_cast<std::uint16_t>(bytes_.size() - kDatagramOverhead); }
    bool circulating() const { return (load_le<std::uint16_t>(bytes_, 6) & kCirculatingBit) != 0; }
    bool more() const { return (load_le<std::uint16_t>(bytes_, 6) & kMoreBit) != 0; }

    std::span<Byte> data() const { return bytes_.subspan(kDatagramHeaderSize, length()); }
    std::uint16_t wkc() const { return load_le<std::uint16_t>(bytes_, bytes_.size() - kWkcSize); }

    // Offset of the datagram header from the start of the Ethernet frame.
    std::size_t frame_offset() const { return frame_offset_; }
    std::size_t size() const { return bytes_.size(); }
    std::span<Byte> bytes() const { return bytes_; }

    void set_wkc(std::uint16_t wkc) const
        requires kMutable
    {
        store_le<std::uint16_t>(bytes_, bytes_.size() - kWkcSize, wkc);
    }
    void set_index(std::uint8_t index) const
        requires kMutable
    {
        bytes_[1] = index;
    }
    void set_address(std::uint32_t address) const
        requires kMutable
    {
        store_le<std::uint32_t>(bytes_, 2, address);
    }
    void set_circulating(bool on) const
        requires kMutable
    {
        auto word = load_le<std::uint16_t>(bytes_, 6);
        word = static_cast<std::uint16_t>(on ? (word | kCirculatingBit) : (word & ~kCirculatingBit));
        store_le<std::uint16_t>(bytes_, 6, word);
    }
    void set_irq(std::uint16_t irq) const
        requires kMutable
    {
        store_le<std::uint16_t>(bytes_, 8, irq);
    }
    std::uint16_t irq() const { return load_le<std::uint16_t>(bytes_, 8); }

private:
    std::span<Byte> bytes_;
    std::size_t frame_offset_;
};

using DatagramView = BasicDatagramView<std::uint8_t>;
using ConstDatagramView = BasicDatagramView<const std::uint8_t>;

}  // namespace ecpair::wire
