// The bridge datagram codec. decode_bridge_datagram() checks in the order a
// reader would trust things: the fixed fields, the length against the
// datagram, the CRC over what the length covers, and only then the packed
// frames, so that a garbled length can never make it read outside `data`.

#include "ecpair/tap_bridge/bridge_datagram.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/crc32.hpp"

namespace ecpair::tap_bridge {
namespace {

// Offsets in the header (WIRE_FORMAT.md §11.2).
constexpr std::size_t kVersionAt = 2;
constexpr std::size_t kKindAt = 3;
constexpr std::size_t kLengthAt = 4;
constexpr std::size_t kFrameCountAt = 6;
constexpr std::size_t kReserved1At = 7;
constexpr std::size_t kSessionAt = 8;
constexpr std::size_t kSequenceAt = 12;
constexpr std::size_t kBacklogAt = 16;
constexpr std::size_t kReserved2At = 18;
constexpr std::size_t kCrcAt = 20;

std::uint32_t checksum(ConstBytes data, std::size_t length) {
    return crc32(data.subspan(kBridgeHeaderSize, length), crc32(data.first(kCrcAt)));
}

bool known_kind(std::uint8_t value) {
    switch (static_cast<BridgeKind>(value)) {
        case BridgeKind::Data:
        case BridgeKind::Poll:
        case BridgeKind::Answer: return true;
    }
    return false;
}

template <class View>
bool bridge_datagram(const View& datagram) {
    const auto data = datagram.data();
    return datagram.command() == wire::Command::Nop &&
           datagram.address() == wire::DatagramHeader::physical(0, kBridgeAdo) && data.size() >= 2 &&
           data[0] == BridgeHeader::kMagic[0] && data[1] == BridgeHeader::kMagic[1];
}

}  // namespace

std::optional<BridgeKind> peek_kind(ConstBytes data) {
    if (data.size() <= kKindAt) return std::nullopt;
    return static_cast<BridgeKind>(data[kKindAt]);
}

std::string_view to_string(BridgeKind kind) {
    switch (kind) {
        case BridgeKind::Data: return "DATA";
        case BridgeKind::Poll: return "POLL";
        case BridgeKind::Answer: return "ANSWER";
    }
    return "?";
}

std::string_view to_string(BridgeErrc code) {
    switch (code) {
        case BridgeErrc::Truncated: return "Truncated";
        case BridgeErrc::BadMagic: return "BadMagic";
        case BridgeErrc::UnsupportedVersion: return "UnsupportedVersion";
        case BridgeErrc::UnknownKind: return "UnknownKind";
        case BridgeErrc::ReservedSet: return "ReservedSet";
        case BridgeErrc::BadChecksum: return "BadChecksum";
        case BridgeErrc::BadFrameLength: return "BadFrameLength";
        case BridgeErrc::FrameCountMismatch: return "FrameCountMismatch";
        case BridgeErrc::PollNotEmpty: return "PollNotEmpty";
    }
    return "?";
}

std::string BridgeError::describe() const {
    return fmt::format("bridge datagram {} at frame offset {} (found {:#x})", to_string(code), offset, found);
}

bool is_bridge_datagram(const wire::ConstDatagramView& datagram) { return bridge_datagram(datagram); }
bool is_bridge_datagram(const wire::DatagramView& datagram) { return bridge_datagram(datagram); }

Expected<BridgeDatagram, BridgeError> decode_bridge_datagram(ConstBytes data, std::size_t data_offset) {
    auto fail = [data_offset](BridgeErrc code, std::size_t at, std::uint64_t found) {
        return unexpected(BridgeError{code, data_offset + at, found});
    };
    if (data.size() < kBridgeHeaderSize) return fail(BridgeErrc::Truncated, 0, data.size());
    if (data[0] != BridgeHeader::kMagic[0] || data[1] != BridgeHeader::kMagic[1]) {
        return fail(BridgeErrc::BadMagic, 0, load_le<std::uint16_t>(data, 0));
    }
    if (data[kVersionAt] != kBridgeFormatVersion) return fail(BridgeErrc::UnsupportedVersion, kVersionAt, data[kVersionAt]);
    if (!known_kind(data[kKindAt])) return fail(BridgeErrc::UnknownKind, kKindAt, data[kKindAt]);
    if (data[kReserved1At] != 0) return fail(BridgeErrc::ReservedSet, kReserved1At, data[kReserved1At]);
    if (load_le<std::uint16_t>(data, kReserved2At) != 0) {
        return fail(BridgeErrc::ReservedSet, kReserved2At, load_le<std::uint16_t>(data, kReserved2At));
    }
    BridgeDatagram out;
    BridgeHeader& h = out.header;
    h.version = data[kVersionAt];
    h.kind = static_cast<BridgeKind>(data[kKindAt]);
    h.length = load_le<std::uint16_t>(data, kLengthAt);
    h.frame_count = data[kFrameCountAt];
    h.session = load_le<std::uint32_t>(data, kSessionAt);
    h.sequence = load_le<std::uint32_t>(data, kSequenceAt);
    h.backlog = load_le<std::uint16_t>(data, kBacklogAt);
    if (h.length > data.size() - kBridgeHeaderSize) return fail(BridgeErrc::Truncated, kLengthAt, h.length);
    const std::uint32_t crc = load_le<std::uint32_t>(data, kCrcAt);
    if (checksum(data, h.length) != crc) return fail(BridgeErrc::BadChecksum, kCrcAt, crc);
    if (h.kind == BridgeKind::Poll && (h.length != 0 || h.frame_count != 0)) {
        return fail(BridgeErrc::PollNotEmpty, kLengthAt, h.length);
    }

    out.payload = data.subspan(kBridgeHeaderSize, h.length);
    out.data_offset = data_offset;
    std::size_t at = 0;
    std::size_t frames = 0;
    while (at < out.payload.size()) {
        if (at + kFrameLengthPrefix > out.payload.size()) {
            return fail(BridgeErrc::BadFrameLength, kBridgeHeaderSize + at, out.payload.size() - at);
        }
        const std::size_t length = load_le<std::uint16_t>(out.payload, at);
        if (length < kMinBridgedFrame || at + kFrameLengthPrefix + length > out.payload.size()) {
            return fail(BridgeErrc::BadFrameLength, kBridgeHeaderSize + at, length);
        }
        at += kFrameLengthPrefix + length;
        ++frames;
    }
    if (frames != h.frame_count) return fail(BridgeErrc::FrameCountMismatch, kFrameCountAt, h.frame_count);
    return out;
}

BridgePayloadWriter::BridgePayloadWriter(Bytes data) : data_(data) {}

bool BridgePayloadWriter::add(ConstBytes frame) {
    if (!fits(frame.size())) return false;
    const Bytes payload = data_.subspan(kBridgeHeaderSize);
    store_le<std::uint16_t>(payload, used_, static_cast<std::uint16_t>(frame.size()));
    std::copy(frame.begin(), frame.end(), payload.begin() + static_cast<std::ptrdiff_t>(used_ + kFrameLengthPrefix));
    used_ += kFrameLengthPrefix + frame.size();
    ++frame_count_;
    return true;
}

std::size_t BridgePayloadWriter::seal(BridgeKind kind, std::uint32_t session, std::uint32_t sequence,
                                      std::uint16_t backlog) {
    data_[0] = BridgeHeader::kMagic[0];
    data_[1] = BridgeHeader::kMagic[1];
    data_[kVersionAt] = kBridgeFormatVersion;
    data_[kKindAt] = static_cast<std::uint8_t>(kind);
    store_le<std::uint16_t>(data_, kLengthAt, static_cast<std::uint16_t>(used_));
    data_[kFrameCountAt] = frame_count_;
    data_[kReserved1At] = 0;
    store_le<std::uint32_t>(data_, kSessionAt, session);
    store_le<std::uint32_t>(data_, kSequenceAt, sequence);
    store_le<std::uint16_t>(data_, kBacklogAt, backlog);
    store_le<std::uint16_t>(data_, kReserved2At, 0);
    const auto unused = data_.subspan(kBridgeHeaderSize + used_);
    std::fill(unused.begin(), unused.end(), std::uint8_t{0});
    store_le<std::uint32_t>(data_, kCrcAt, checksum(data_, used_));
    return kBridgeHeaderSize + used_;
}

}  // namespace ecpair::tap_bridge
