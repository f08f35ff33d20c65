#pragma once
// Hot-Connect's events (docs/HOT_CONNECT.md): how a topology change ended,
// groups added or probed, groups waiting for an accept, port loop settings.
// Group masks cover groups 1..32. The master's events (bus scan, mismatch,
// presence) that Hot-Connect raises too are in master_events.hpp.

#include <cstdint>
#include <string_view>

#include "ecpair/master/event.hpp"

namespace ecpair::hotconnect::events {

extern const master::EventType kTopologyChangeDone;       // a = TopologyResult, b = optional groups present, c = optional groups, d = WKC deviations
extern const master::EventType kDetectAddGroups;          // a = TopologyResult, b = optional groups, c = groups present, d = presence mask
extern const master::EventType kProbeAllGroups;           // as kDetectAddGroups, after groups went away
extern const master::EventType kHotConnectAcceptPending;  // a = groups waiting for an accept, b = mask of them
extern const master::EventType kPortLoopChanged;          // a = station, b = port (0..3), c = loop setting (0 auto .. 3 closed), d = PortLoopReason

}  // namespace ecpair::hotconnect::events

namespace ecpair::hotconnect {

// How a Hot-Connect topology change ended (kTopologyChangeDone, kDetectAddGroups, kProbeAllGroups: a).
enum class TopologyResult : std::uint8_t {
    Ok = 0,
    GroupsRefused = 1,     // a group or slave did not match the ENI: left out, the rest goes on
    MandatoryMissing = 2,  // a mandatory slave is not there (cyclic WKC errors follow)
    BringUpFailed = 3,     // a group did not reach the master state
    ScanFailed = 4,        // the bus could not be scanned
    Timeout = 5,           // the bus did not settle within the detection timeout
    Cancelled = 6,         // the master stopped or became INACTIVE meanwhile
};
std::string_view to_string(TopologyResult result);

// Why a port's loop setting changed (kPortLoopChanged, d).
enum class PortLoopReason : std::uint8_t {
    ByOperator = 0,
    BorderClose = 1,  // no group may join there
    BlockNode = 2,    // cut off what hangs behind it
    OpenBlocked = 3,  // a blocked port opened again
};

}  // namespace ecpair::hotconnect
