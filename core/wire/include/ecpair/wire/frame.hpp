#pragma once
// EtherCAT frames: Ethernet header (optionally VLAN-tagged), the 2-byte
// EtherCAT header, datagrams chained by their M bit, padding to 60 bytes.
//
// FrameView::parse validates a whole frame once (every datagram header and
// length within the buffer) and then hands out datagram views without further
// checks. Nothing is allocated, so the cycle path and ecsim can use it per
// frame. FrameBuilder writes a frame into a caller-owned buffer.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <span>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/decode_error.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::wire {

struct EthernetHeader {
    MacAddress destination;
    MacAddress source;
    std::optional<std::uint16_t> vlan_tci;  // present when the frame is 802.1Q tagged
    std::uint16_t ether_type = kEtherTypeEtherCat;

    std::size_t size() const { return vlan_tci ? kEthernetHeaderSize + kVlanTagSize : kEthernetHeaderSize; }
    void encode(Bytes out) const;  // out.size() >= size()
    static Expected<EthernetHeader, DecodeError> decode(ConstBytes frame);
};

struct EcatHeader {
    std::uint16_t length = 0;  // 11 bits: bytes of all datagrams, padding excluded
    bool reserved = false;
    std::uint8_t type = kEcatTypeDatagrams;  // 4 bits

    void encode(Bytes out) const;  // 2 bytes
    static EcatHeader decode(ConstBytes in);
};

template <class Byte>
class BasicFrameView {
public:
    using Datagram = BasicDatagramView<Byte>;

    static Expected<BasicFrameView, DecodeError> parse(std::span<Byte> frame);

    const EthernetHeader& ethernet() const { return ethernet_; }
    EcatHeader ecat_header() const { return EcatHeader::decode(bytes_.subspan(ecat_offset_)); }
    std::size_t ecat_offset() const { return ecat_offset_; }
    std::size_t datagram_count() const { return datagram_count_; }
    // First byte after the last datagram's WKC; what follows is padding.
    std::size_t end_offset() const { return end_offset_; }
    std::span<Byte> bytes() const { return bytes_; }

    // Rewrites the source MAC in the buffer (and in ethernet()).
    void set_source(const MacAddress& source)
        requires(!std::is_const_v<Byte>)
    {
        ethernet_.source = source;
        std::copy(source.bytes.begin(), source.bytes.end(), bytes_.begin() + 6);
    }

    class iterator {
    public:
        using iterator_category = std::forward_iterator_tag;
        using value_type = Datagram;
        using difference_type = std::ptrdiff_t;
        using pointer = void;
        using reference = Datagram;

        iterator() = default;
        iterator(std::span<Byte> frame, std::size_t offset, std::size_t remaining)
            : frame_(frame), offset_(offset), remaining_(remaining) {}
        Datagram operator*() const {
            const std::size_t len = load_le<std::uint16_t>(frame_, offset_ + 6) & kLengthMask;
            return Datagram(frame_.subspan(offset_, kDatagramOverhead + len), offset_);
        }
        iterator& operator++() {
            const std::size_t len = load_le<std::uint16_t>(frame_, offset_ + 6) & kLengthMask;
            offset_ += kDatagramOverhead + len;
            --remaining_;
            return *this;
        }
        iterator operator++(int) {
            auto copy = *this;
            ++*this;
            return copy;
        }
        friend bool operator==(const iterator& a, const iterator& b) { return a.remaining_ == b.remaining_; }

    private:
        std::span<Byte> frame_;
        std::size_t offset_ = 0;
        std::size_t remaining_ = 0;
    };

    iterator begin() const { return iterator(bytes_, ecat_offset_ + kEcatHeaderSize, datagram_count_); }
    iterator end() const { return iterator(bytes_, end_offset_, 0); }

private:
    BasicFrameView(std::span<Byte> bytes, EthernetHeader ethernet, std::size_t ecat_offset,
                   std::size_t datagram_count, std::size_t end_offset)
        : bytes_(bytes), ethernet_(ethernet), ecat_offset_(ecat_offset),
          datagram_count_(datagram_count), end_offset_(end_offset) {}

    std::span<Byte> bytes_;
    EthernetHeader ethernet_;
    std::size_t ecat_offset_ = 0;
    std::size_t datagram_count_ = 0;
    std::size_t end_offset_ = 0;
};

using FrameView = BasicFrameView<std::uint8_t>;
using ConstFrameView = BasicFrameView<const std::uint8_t>;

extern template Expected<BasicFrameView<std::uint8_t>, DecodeError> BasicFrameView<std::uint8_t>::parse(
    std::span<std::uint8_t>);
extern template Expected<BasicFrameView<const std::uint8_t>, DecodeError> BasicFrameView<const std::uint8_t>::parse(
    std::span<const std::uint8_t>);

// Writes one frame into a caller-owned buffer: Ethernet header, EtherCAT
// header, datagrams; finish() fills in the EtherCAT length, sets the M bits
// and pads to the 60-byte minimum.
class FrameBuilder {
public:
    // buffer must hold at least kMinFrameSize bytes; its size caps the frame.
    explicit FrameBuilder(Bytes buffer, const EthernetHeader& ethernet);

    // Appends a datagram with the header's command/index/address/irq/circulating
    // and `data` as its payload (length and M bit are managed here). Returns the
    // view of the new datagram, or nullopt when it does not fit.
    std::optional<DatagramView> append(const DatagramHeader& header, ConstBytes data);
    // Same with `data_length` zero bytes.
    std::optional<DatagramView> append(const DatagramHeader& header, std::size_t data_length);

    // Largest data length another datagram could still carry.
    std::size_t remaining_data_capacity() const;
    std::size_t datagram_count() const { return datagram_count_; }

    // The finished frame (at least kMinFrameSize bytes). The builder may keep
    // appending afterwards; finish() again gives the longer frame.
    Bytes finish();

private:
    Bytes buffer_;
    std::size_t ecat_offset_;
    std::size_t end_ = 0;
    std::size_t last_datagram_ = 0;
    std::size_t datagram_count_ = 0;
};

// Pads `frame` (of `size` bytes inside a buffer of at least kMinFrameSize) with
// zeros up to the 60-byte minimum, as a NIC does on transmit. Returns the new size.
std::size_t pad_to_minimum(Bytes buffer, std::size_t size);

}  // namespace ecpair::wire
