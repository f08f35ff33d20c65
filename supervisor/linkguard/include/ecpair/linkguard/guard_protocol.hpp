#pragma once
// What ecpaird and its link guard (ecpair-linkguard) say to each other over
// the SOCK_SEQPACKET socket pair that ties them: one fixed-size message per
// datagram (docs/WIRE_FORMAT.md, "Link guard messages"). The socket is also
// the guard's lifeline: when ecpaird dies, for any reason, the kernel closes
// its end and the guard reads end-of-file.
//
//   ecpaird -> guard   Heartbeat (the cycle counter, sent only while it advances),
//                      LinksUp (bring MAIN and RED up), Shutdown (links down, exit)
//   guard -> ecpaird   LinksAreUp (answer to LinksUp), LinksTakenDown (the guard
//                      acted: why, after how long), HeartbeatResumed (the cycle
//                      advances again; the links stay down until LinksUp)
//
// Bytes from the socket are untrusted: decode() checks everything and says
// what is wrong.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"

namespace ecpair::linkguard {

enum class GuardMessageKind : std::uint8_t {
    Heartbeat = 1,
    LinksUp = 2,
    Shutdown = 3,
    LinksAreUp = 16,
    LinksTakenDown = 17,
    HeartbeatResumed = 18,
};
std::string_view to_string(GuardMessageKind kind);

// Why the guard took the links down.
enum class DownReason : std::uint8_t {
    None = 0,
    HeartbeatStopped = 1,  // the cycle did not advance for hang_timeout (a hang, SIGSTOP...)
    DaemonGone = 2,        // the socket closed: ecpaird died (kill -9 included)
    DaemonStopping = 3,    // ecpaird shuts down and asked for it
};
std::string_view describe(DownReason reason);

// Which links a message is about.
inline constexpr std::uint8_t kMainLink = 1u << 0;
inline constexpr std::uint8_t kRedLink = 1u << 1;
std::string links_text(std::uint8_t links);  // "MAIN and RED", "MAIN", "no link"

struct GuardMessage {
    GuardMessageKind kind = GuardMessageKind::Heartbeat;
    DownReason reason = DownReason::None;  // LinksTakenDown
    std::uint8_t links = 0;                // LinksAreUp / LinksTakenDown: the links now in the wanted state
    std::uint32_t silence_ms = 0;          // LinksTakenDown / HeartbeatResumed: time without a heartbeat;
                                           // LinksAreUp: how long the guard had kept the links down
    std::int32_t error = 0;                // errno of the first link that could not be set (0: none)
    std::uint64_t cycle = 0;               // Heartbeat: the cycle; otherwise the last heartbeat's cycle

    bool operator==(const GuardMessage&) const = default;
};

inline constexpr std::size_t kGuardMessageSize = 24;
inline constexpr std::uint8_t kGuardProtocolVersion = 1;

std::array<std::uint8_t, kGuardMessageSize> encode(const GuardMessage& message);

struct GuardDecodeError {
    std::size_t offset = 0;
    std::string problem;
};
Expected<GuardMessage, GuardDecodeError> decode(ConstBytes datagram);

}  // namespace ecpair::linkguard
