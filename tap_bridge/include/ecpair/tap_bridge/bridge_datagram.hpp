#pragma once
// The TAP bridge's datagram, format version 1 (docs/WIRE_FORMAT.md §11).
//
// Master-to-master Ethernet frames (what the kernel's TAP device hands us)
// travel in Acyclic Master Red Frames: NOP datagrams addressed ADP 0 /
// ADO 0x4254 that no slave processes. Each datagram carries a 24-byte
// bridge header and whole Ethernet frames packed one after the other, each
// behind its 2-byte length; a frame is never cut across datagrams (so the
// TAP's MTU is what fits one datagram of one EtherCAT frame).
//
//   DATA    the ACTIVE's frames for the INACTIVE
//   POLL    room the ACTIVE offers its partner (no frames, sequence = poll id)
//   ANSWER  a POLL the INACTIVE filled with its frames as it forwarded it
//
// Every datagram names the instance that wrote it (a session id chosen at
// start) and that writer's sequence number, so that a receiver delivers
// each datagram once, in order, whichever of its MAIN and RED copies comes
// first. A CRC-32 over header and payload catches garbled datagrams: what
// decode() accepts can be delivered to the TAP as it is.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/datagram.hpp"

namespace ecpair::tap_bridge {

inline constexpr std::uint8_t kBridgeFormatVersion = 1;
// The datagram's ADO: not the CMF's 0x4155, and no ESC register an ADP 0 NOP could mean.
inline constexpr std::uint16_t kBridgeAdo = 0x4254;

enum class BridgeKind : std::uint8_t { Data = 1, Poll = 2, Answer = 3 };
std::string_view to_string(BridgeKind kind);

// The kind byte of a bridge datagram's data, without decode's checks: the
// quick look that decides whether a datagram needs decoding at all.
// nullopt when the data is too short to hold it; any other byte is returned
// as it is (a value no BridgeKind names compares unequal to all of them).
std::optional<BridgeKind> peek_kind(ConstBytes data);

// Sizes: one datagram fills one EtherCAT frame at most (1486 data bytes).
inline constexpr std::size_t kBridgeHeaderSize = 24;
inline constexpr std::size_t kFrameLengthPrefix = 2;
inline constexpr std::size_t kMaxBridgeDatagramData = wire::kMaxDatagramData;                     // 1486
inline constexpr std::size_t kMaxBridgePayload = kMaxBridgeDatagramData - kBridgeHeaderSize;    // 1462
inline constexpr std::size_t kMinBridgedFrame = wire::kEthernetHeaderSize;                      // 14
// The smallest poll that still carries one minimal frame.
inline constexpr std::size_t kMinPollData = kBridgeHeaderSize + kFrameLengthPrefix + kMinBridgedFrame;  // 40

// The largest Ethernet frame (without FCS) a datagram of `datagram_data` bytes carries.
constexpr std::size_t largest_frame(std::size_t datagram_data) {
    return datagram_data < kBridgeHeaderSize + kFrameLengthPrefix ? 0
                                                                  : datagram_data - kBridgeHeaderSize - kFrameLengthPrefix;
}
// The largest TAP MTU (IP packet bytes) whose frames fit a poll of
// `poll_data` bytes and a DATA datagram: 1446 with the largest poll.
constexpr std::size_t largest_mtu(std::size_t poll_data = kMaxBridgeDatagramData) {
    const std::size_t frame = largest_frame(poll_data < kMaxBridgeDatagramData ? poll_data : kMaxBridgeDatagramData);
    return frame < wire::kEthernetHeaderSize ? 0 : frame - wire::kEthernetHeaderSize;
}

// ---- errors

enum class BridgeErrc : std::uint8_t {
    Truncated,           // fewer bytes than the header, or than its length says
    BadMagic,            // the data does not start with "TB"
    UnsupportedVersion,  // a format version other than kBridgeFormatVersion
    UnknownKind,         // not DATA, POLL or ANSWER
    ReservedSet,         // a reserved byte is not 0
    BadChecksum,         // the CRC-32 does not match header and payload
    BadFrameLength,      // a packed frame shorter than an Ethernet header or running past the payload
    FrameCountMismatch,  // the packed frames are not as many as the header says
    PollNotEmpty,        // a POLL that carries frames
};
std::string_view to_string(BridgeErrc code);

struct BridgeError {
    BridgeErrc code = BridgeErrc::Truncated;
    std::size_t offset = 0;   // byte offset in the Ethernet frame (or in the decoded bytes)
    std::uint64_t found = 0;  // the offending value
    // "bridge datagram BadChecksum at frame offset 40 (found 0x1234abcd)"
    std::string describe() const;
};

// ---- the header (24 bytes at the start of the datagram's data)

struct BridgeHeader {
    static constexpr std::uint8_t kMagic[2] = {'T', 'B'};

    std::uint8_t version = kBridgeFormatVersion;
    BridgeKind kind = BridgeKind::Data;
    std::uint16_t length = 0;      // payload bytes used: the packed frames with their length prefixes
    std::uint8_t frame_count = 0;  // packed frames
    std::uint32_t session = 0;     // the writer's session id (random per start)
    std::uint32_t sequence = 0;    // DATA/ANSWER: the writer's datagram number; POLL: the poll's number
    std::uint16_t backlog = 0;     // bytes still queued at the writer after this datagram (saturates)

    friend bool operator==(const BridgeHeader&, const BridgeHeader&) = default;
};

// A datagram's data (header + payload) as decode() found it valid.
struct BridgeDatagram {
    BridgeHeader header;
    ConstBytes payload;          // header.length bytes of packed frames
    std::size_t data_offset = 0; // of the datagram's data in the Ethernet frame

    // Calls visit(frame) for each packed Ethernet frame, in order.
    template <class Visit>
    void for_each_frame(Visit&& visit) const {
        std::size_t at = 0;
        while (at + kFrameLengthPrefix <= payload.size()) {
            const std::size_t length = load_le<std::uint16_t>(payload, at);
            visit(payload.subspan(at + kFrameLengthPrefix, length));
            at += kFrameLengthPrefix + length;
        }
    }
};

// A NOP datagram at ADP 0 / ADO 0x4254 whose data starts with the magic "TB".
bool is_bridge_datagram(const wire::ConstDatagramView& datagram);
bool is_bridge_datagram(const wire::DatagramView& datagram);

// Checks everything (magic, version, kind, reserved bytes, length within the
// data, CRC, every packed frame) before anything of it is trusted. `data` is
// the datagram's data, `data_offset` its offset in the frame (for errors).
Expected<BridgeDatagram, BridgeError> decode_bridge_datagram(ConstBytes data, std::size_t data_offset = 0);

// Packs frames into a datagram's data and seals it with header and CRC.
// Works in place on the caller's buffer (the frame being built): nothing is
// allocated.
class BridgePayloadWriter {
public:
    // `data` is the whole data of the datagram (header included), at least kBridgeHeaderSize bytes.
    explicit BridgePayloadWriter(Bytes data);

    // Whether a frame of `size` bytes would still fit.
    bool fits(std::size_t size) const { return used_ + kFrameLengthPrefix + size <= room() && frame_count_ < 255; }
    // Appends a frame; false (and nothing written) when it does not fit.
    bool add(ConstBytes frame);
    std::size_t room() const { return data_.size() - kBridgeHeaderSize; }
    std::size_t used() const { return used_; }
    std::uint8_t frame_count() const { return frame_count_; }

    // Writes the header (length and frame count from what was added), zeros
    // the unused rest of the data, and the CRC. Returns the bytes used in the
    // data (header + payload).
    std::size_t seal(BridgeKind kind, std::uint32_t session, std::uint32_t sequence, std::uint16_t backlog);

private:
    Bytes data_;
    std::size_t used_ = 0;
    std::uint8_t frame_count_ = 0;
};

}  // namespace ecpair::tap_bridge
