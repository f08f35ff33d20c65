#pragma once
// The redundancy's events: a pair member's role changes at the cycle
// boundary, the takeover, a partner that runs something else, and the
// background scan that verifies a mirrored topology after a hot takeover.

#include <cstdint>

#include "ecpair/master/event.hpp"

namespace ecpair::redundancy::events {

extern const master::EventType kRedStateChanged;    // a = from, b = to (RedState: 0 INACTIVE, 1 ACTIVE)
extern const master::EventType kTakeover;           // a = 1 hot / 0 cold, b = the master state taken over
extern const master::EventType kPartnerMismatch;    // a = what differs (kDiffers* bits)
extern const master::EventType kTopologyVerified;   // a = 1 if the background scan matches the mirrored image
// The ACTIVE sent no CMF this cycle: a = CmfWriteError::What, b = expected, c = actual. Summarised per What.
extern const master::EventType kCmfNotSent;
// The INACTIVE's kernel program kept its old answer: a = errno of the map update. Summarised per errno.
extern const master::EventType kKernelAnswerNotUpdated;

}  // namespace ecpair::redundancy::events

namespace ecpair::redundancy {

// What differs from a redundant partner (events::kPartnerMismatch, a).
inline constexpr std::uint32_t kDiffersEni = 1u << 0;
inline constexpr std::uint32_t kDiffersCycleTime = 1u << 1;
inline constexpr std::uint32_t kDiffersCableRedundancy = 1u << 2;
inline constexpr std::uint32_t kDiffersSplitLrw = 1u << 3;
inline constexpr std::uint32_t kDiffersMasterPdOut = 1u << 4;
inline constexpr std::uint32_t kDiffersMasterPdIn = 1u << 5;
inline constexpr std::uint32_t kDiffersUpdateSlavePdIn = 1u << 6;
inline constexpr std::uint32_t kDiffersUpdateSlavePdOut = 1u << 7;
inline constexpr std::uint32_t kDiffersMaxAcycFrames = 1u << 8;
inline constexpr std::uint32_t kDiffersLayout = 1u << 9;

}  // namespace ecpair::redundancy
