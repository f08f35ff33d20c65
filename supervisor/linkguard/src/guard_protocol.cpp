// Layout (little endian): version u8, kind u8, reason u8, links u8,
// silence_ms u32, error i32, reserved u32 (zero), cycle u64.

#include "ecpair/linkguard/guard_protocol.hpp"

#include <fmt/format.h>

namespace ecpair::linkguard {
namespace {

constexpr std::size_t kVersionAt = 0;
constexpr std::size_t kKindAt = 1;
constexpr std::size_t kReasonAt = 2;
constexpr std::size_t kLinksAt = 3;
constexpr std::size_t kSilenceAt = 4;
constexpr std::size_t kErrorAt = 8;
constexpr std::size_t kReservedAt = 12;
constexpr std::size_t kCycleAt = 16;

bool known_kind(std::uint8_t kind) {
    switch (static_cast<GuardMessageKind>(kind)) {
        case GuardMessageKind::Heartbeat:
        case GuardMessageKind::LinksUp:
        case GuardMessageKind::Shutdown:
        case GuardMessageKind::LinksAreUp:
        case GuardMessageKind::LinksTakenDown:
        case GuardMessageKind::HeartbeatResumed: return true;
    }
    return false;
}

template <class T>
void put(std::array<std::uint8_t, kGuardMessageSize>& out, std::size_t at, T value) {
    for (std::size_t i = 0; i < sizeof(T); ++i) out[at + i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i));
}

template <class T>
T get(ConstBytes in, std::size_t at) {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) value |= std::uint64_t{in[at + i]} << (8 * i);
    return static_cast<T>(value);
}

Unexpected<GuardDecodeError> problem(std::size_t offset, std::string text) {
    return unexpected(GuardDecodeError{offset, std::move(text)});
}

}  // namespace

std::string_view to_string(GuardMessageKind kind) {
    switch (kind) {
        case GuardMessageKind::Heartbeat: return "heartbeat";
        case GuardMessageKind::LinksUp: return "links-up";
        case GuardMessageKind::Shutdown: return "shutdown";
        case GuardMessageKind::LinksAreUp: return "links-are-up";
        case GuardMessageKind::LinksTakenDown: return "links-taken-down";
        case GuardMessageKind::HeartbeatResumed: return "heartbeat-resumed";
    }
    return "unknown";
}

std::string_view describe(DownReason reason) {
    switch (reason) {
        case DownReason::None: return "no reason";
        case DownReason::HeartbeatStopped: return "ecpaird's cycle stopped advancing (hang)";
        case DownReason::DaemonGone: return "ecpaird is gone (its end of the guard socket closed)";
        case DownReason::DaemonStopping: return "ecpaird is shutting down";
    }
    return "unknown reason";
}

std::string links_text(std::uint8_t links) {
    const bool main = (links & kMainLink) != 0;
    const bool red = (links & kRedLink) != 0;
    if (main && red) return "MAIN and RED";
    if (main) return "MAIN";
    if (red) return "RED";
    return "no link";
}

std::array<std::uint8_t, kGuardMessageSize> encode(const GuardMessage& m) {
    std::array<std::uint8_t, kGuardMessageSize> out{};
    put(out, kVersionAt, kGuardProtocolVersion);
    put(out, kKindAt, static_cast<std::uint8_t>(m.kind));
    put(out, kReasonAt, static_cast<std::uint8_t>(m.reason));
    put(out, kLinksAt, m.links);
    put(out, kSilenceAt, m.silence_ms);
    put(out, kErrorAt, static_cast<std::uint32_t>(m.error));
    put(out, kReservedAt, std::uint32_t{0});
    put(out, kCycleAt, m.cycle);
    return out;
}

Expected<GuardMessage, GuardDecodeError> decode(ConstBytes in) {
    if (in.size() != kGuardMessageSize) {
        return problem(0, fmt::format("a link guard message has {} bytes (got {})", kGuardMessageSize, in.size()));
    }
    if (in[kVersionAt] != kGuardProtocolVersion) {
        return problem(kVersionAt, fmt::format("protocol version {} (this program speaks {})", in[kVersionAt],
                                               kGuardProtocolVersion));
    }
    if (!known_kind(in[kKindAt])) return problem(kKindAt, fmt::format("unknown message kind {}", in[kKindAt]));
    if (in[kReasonAt] > static_cast<std::uint8_t>(DownReason::DaemonStopping)) {
        return problem(kReasonAt, fmt::format("unknown reason {}", in[kReasonAt]));
    }
    if ((in[kLinksAt] & ~(kMainLink | kRedLink)) != 0) {
        return problem(kLinksAt, fmt::format("unknown link bits 0x{:02x}", in[kLinksAt]));
    }
    if (get<std::uint32_t>(in, kReservedAt) != 0) return problem(kReservedAt, "reserved bytes are not zero");
    GuardMessage m;
    m.kind = static_cast<GuardMessageKind>(in[kKindAt]);
    m.reason = static_cast<DownReason>(in[kReasonAt]);
    m.links = in[kLinksAt];
    m.silence_ms = get<std::uint32_t>(in, kSilenceAt);
    m.error = static_cast<std::int32_t>(get<std::uint32_t>(in, kErrorAt));
    m.cycle = get<std::uint64_t>(in, kCycleAt);
    return m;
}

}  // namespace ecpair::linkguard
