#include "ecpair/wire/frame.hpp"

#include <algorithm>
#include <cassert>

namespace ecpair::wire {

void EthernetHeader::encode(Bytes out) const {
    std::copy(destination.bytes.begin(), destination.bytes.end(), out.begin());
    std::copy(source.bytes.begin(), source.bytes.end(), out.begin() + 6);
    std::size_t offset = 12;
    if (vlan_tci) {
        store_be16(out, offset, kEtherTypeVlan);
        store_be16(out, offset + 2, *vlan_tci);
        offset += kVlanTagSize;
    }
    store_be16(out, offset, ether_type);
}

Expected<EthernetHeader, DecodeError> EthernetHeader::decode(ConstBytes frame) {
    if (frame.size() < kEthernetHeaderSize) {
        return unexpected(DecodeError{DecodeErrc::TruncatedEthernetHeader, 0, frame.size()});
    }
    EthernetHeader h;
    std::copy_n(frame.begin(), 6, h.destination.bytes.begin());
    std::copy_n(frame.begin() + 6, 6, h.source.bytes.begin());
    std::size_t offset = 12;
    std::uint16_t type = load_be16(frame, offset);
    if (type == kEtherTypeVlan) {
        if (frame.size() < kEthernetHeaderSize + kVlanTagSize) {
            return unexpected(DecodeError{DecodeErrc::TruncatedEthernetHeader, 12, frame.size()});
        }
        h.vlan_tci = load_be16(frame, offset + 2);
        offset += kVlanTagSize;
        type = load_be16(frame, offset);
    }
    h.ether_type = type;
    return h;
}

void EcatHeader::encode(Bytes out) const {
    std::uint16_t word = static_cast<std::uint16_t>(length & kLengthMask);
    if (reserved) word |= 0x0800;
    word = static_cast<std::uint16_t>(word | ((type & 0x0Fu) << 12));
    store_le<std::uint16_t>(out, 0, word);
}

EcatHeader EcatHeader::decode(ConstBytes in) {
    const auto word = load_le<std::uint16_t>(in, 0);
    return EcatHeader{static_cast<std::uint16_t>(word & kLengthMask), (word & 0x0800) != 0,
                      static_cast<std::uint8_t>(word >> 12)};
}

template <class Byte>
Expected<BasicFrameView<Byte>, DecodeError> BasicFrameView<Byte>::parse(std::span<Byte> frame) {
    auto ethernet = EthernetHeader::decode(frame);
    if (!ethernet) return unexpected(ethernet.error());
    const std::size_t ecat_offset = ethernet->size();
    if (ethernet->ether_type != kEtherTypeEtherCat) {
        return unexpected(DecodeError{DecodeErrc::NotEtherCat, ecat_offset - 2, ethernet->ether_type});
    }
    if (frame.size() < ecat_offset + kEcatHeaderSize) {
        return unexpected(DecodeError{DecodeErrc::TruncatedEcatHeader, ecat_offset, frame.size()});
    }
    const auto ecat = EcatHeader::decode(frame.subspan(ecat_offset));
    if (ecat.type != kEcatTypeDatagrams) {
        return unexpected(DecodeError{DecodeErrc::UnsupportedEcatType, ecat_offset, ecat.type});
    }
    // Walk the datagrams the way an ESC does: by their own Len fields, until
    // one has M=0. The EtherCAT header length is not trusted (ESCs ignore it).
    std::size_t offset = ecat_offset + kEcatHeaderSize;
    std::size_t count = 0;
    for (;;) {
        if (frame.size() < offset + kDatagramHeaderSize) {
            return unexpected(DecodeError{DecodeErrc::TruncatedDatagramHeader, offset, frame.size()});
        }
        const auto word = load_le<std::uint16_t>(frame, offset + 6);
        const std::size_t len = word & kLengthMask;
        if (frame.size() < offset + kDatagramOverhead + len) {
            return unexpected(DecodeError{DecodeErrc::DatagramOverrun, offset, len});
        }
        offset += kDatagramOverhead + len;
        ++count;
        if ((word & kMoreBit) == 0) break;
    }
    return BasicFrameView(frame, *ethernet, ecat_offset, count, offset);
}

// Only parse() is defined out of line; instantiating the whole class for
// const bytes would also instantiate the mutators (clang does).
template Expected<BasicFrameView<std::uint8_t>, DecodeError> BasicFrameView<std::uint8_t>::parse(
    std::span<std::uint8_t>);
template Expected<BasicFrameView<const std::uint8_t>, DecodeError> BasicFrameView<const std::uint8_t>::parse(
    std::span<const std::uint8_t>);

FrameBuilder::FrameBuilder(Bytes buffer, const EthernetHeader& ethernet)
    : buffer_(buffer), ecat_offset_(ethernet.size()) {
    assert(buffer.size() >= kMinFrameSize);
    ethernet.encode(buffer_);
    end_ = ecat_offset_ + kEcatHeaderSize;
}

std::size_t FrameBuilder::remaining_data_capacity() const {
    const std::size_t limit = std::min(buffer_.size(), ecat_offset_ + kEcatHeaderSize + kMaxEcatPayload);
    if (end_ + kDatagramOverhead > limit) return 0;
    return std::min(limit - end_ - kDatagramOverhead, kMaxDatagramData);
}

std::optional<DatagramView> FrameBuilder::append(const DatagramHeader& header, std::size_t data_length) {
    if (data_length > remaining_data_capacity()) return std::nullopt;
    if (datagram_count_ > 0) {
        // The previous datagram now has a successor: set its M bit.
        auto word = load_le<std::uint16_t>(buffer_, last_datagram_ + 6);
        store_le<std::uint16_t>(buffer_, last_datagram_ + 6, static_cast<std::uint16_t>(word | kMoreBit));
    }
    DatagramHeader h = header;
    h.length = static_cast<std::uint16_t>(data_length);
    h.more = false;
    h.encode(buffer_.subspan(end_));
    const std::size_t total = kDatagramOverhead + data_length;
    std::fill_n(buffer_.begin() + static_cast<std::ptrdiff_t>(end_ + kDatagramHeaderSize), data_length + kWkcSize,
                std::uint8_t{0});
    last_datagram_ = end_;
    end_ += total;
    ++datagram_count_;
    return DatagramView(buffer_.subspan(last_datagram_, total), last_datagram_);
}

std::optional<DatagramView> FrameBuilder::append(const DatagramHeader& header, ConstBytes data) {
    auto view = append(header, data.size());
    if (view) std::copy(data.begin(), data.end(), view->data().begin());
    return view;
}

Bytes FrameBuilder::finish() {
    EcatHeader ecat;
    ecat.length = static_cast<std::uint16_t>(end_ - ecat_offset_ - kEcatHeaderSize);
    ecat.encode(buffer_.subspan(ecat_offset_));
    const std::size_t size = pad_to_minimum(buffer_, end_);
    return buffer_.first(size);
}

std::size_t pad_to_minimum(Bytes buffer, std::size_t size) {
    if (size >= kMinFrameSize) return size;
    assert(buffer.size() >= kMinFrameSize);
    std::fill(buffer.begin() + static_cast<std::ptrdiff_t>(size), buffer.begin() + kMinFrameSize, std::uint8_t{0});
    return kMinFrameSize;
}

}  // namespace ecpair::wire
