#pragma once
// What the master tells its application and operators, with the names
// EtherCAT users know from commercial masters (design.md §5). Events are
// small values so that the cycle thread can raise them without allocating;
// text is made on the consumer's side: describe() says what the numbers
// say, EventDescriber (event_describer.hpp) names the slaves, frames and
// datagrams from the ENI and the cyclic plan.

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "ecpair/wire/command.hpp"

namespace ecpair::master {

enum class EventKind : std::uint8_t {
    MasterStateChanged,   // a = from state, b = to state
    CyclicWkcError,       // a = frame, b = datagram index (in the plan's frame), c = expected, d = received
    FrameLost,            // a = frame kind, b = frame index (cyclic) / batch (acyclic), c and d: LostFrameDetail
    LineBreak,            // a = slaves reachable from MAIN (break after that position), b = 1 if known
    LineRepaired,
    LinkDown,             // a = link role
    LinkUp,               // a = link role
    BusScanStatus,        // a = slaves found, b = slaves configured, c = 1 if the bus matches
    BusMismatch,          // a = position, b = mismatch kind (bus::SlaveMatch)
    SlavePresence,        // a = slave index (ENI order, from 0), b = 1 present / 0 absent
    SlaveStateError,      // a = slave index, b = AL status, c = AL status code
    TransitionFailed,     // a = from state, b = to state, c = slave index or 0xFFFF for the master
    FrameResponseError,   // a = reason (FrameResponseReason), b = link role
    RedStateChanged,      // a = from, b = to (redundancy::RedState)
    PartnerLost,          // a = age of the partner's last answer in ms
    PartnerFound,         // a = ms without an answer before (0: first answer)
    PartnerMismatch,      // a = what differs (kDiffers* bits)
    Takeover,             // a = 1 hot / 0 cold, b = the master state taken over
    HandOff,              // a = HandOffPhase, b = the hand-off cycle (low 32 bits), c = HandOffRefusal
    TopologyVerified,     // a = 1 if the background scan matches the mirrored image
    // ---- supervisor and arbitration: a pair member decides its own role
    CommTimeout,          // a = silence in ms, b = the timeout in ms, c = SilenceAction, d = 1 if shortened by a link loss
    AllLinksLost,         // a = 1 if this master was ACTIVE (it stepped down), 0 if INACTIVE (isolated)
    LinksRestored,        // a link is back after all were lost
    FramesNotReturning,   // a = cycles in a row without any frame back, b = 1 right after a takeover
    FramesReturning,      // a = cycles it took
    Collision,            // a = round, b = backoff in µs, c = BackoffCode, d = RuleCode
    ArbitrationSettled,   // a = ArbitrationOutcome, b = our epoch, c = slaves we reach, d = slaves the other reaches (0xFFFF unknown)
    StandbyForced,        // a = 1 forced, 0 released
    NoActiveMaster,       // a = NoActiveReason
    // ops: the link guard (supervisor/linkguard). b = links (bit 0 MAIN, bit 1 RED), d = errno of a failure
    LinkGuardLinksDown,   // a = reason (1 cycle stood still, 3 ecpaird stopping), c = ms without a heartbeat
    LinkGuardResumed,     // c = ms the cycle stood still; the links stay down until ecpaird asks
    LinkGuardLinksUp,     // a = why (0 ecpaird started, 1 the daemon may drive its links again), c = ms they were down
    LinkGuardGone,        // the guard process ended while ecpaird runs: a = its exit status
    // Hot-Connect (issue 10): results are TopologyResult, group masks cover groups 1..32.
    TopologyChangeDetected,      // a = slaves counted before, b = now (0xFFFF: not known), from the cycle
    TopologyChangeDone,          // a = result, b = optional groups present, c = optional groups, d = WKC deviations
    DetectAddGroups,             // a = result, b = optional groups, c = groups present, d = presence mask
    ProbeAllGroups,              // as DetectAddGroups, after groups went away
    BusMismatchIdentification,   // a = position, b = identification Ado, c = value read (0x10000: none), d = expected
    BusMismatchPlace,            // a = position, b = previous station, c = previous port (0..3), d = previous position
    HotConnectAcceptPending,     // a = groups waiting for an accept, b = mask of them
    SlaveIdentificationUpdated,  // a = slave index, b = the station alias now (ETG.1020 code 0x0061)
    PortLoopChanged,             // a = station, b = port (0..3), c = loop setting (0 auto .. 3 closed), d = why
    // The cycle thread (CycleThread's stall): a = µs it woke after its deadline, b = deadlines skipped.
    CycleStall,
    // A slave's CoE emergency (the mailbox service): a = slave index, b = error code | error register << 16,
    // c = data bytes 0-3 (little-endian), d = data byte 4.
    CoeEmergency,
};

// ---- what the supervisor's events carry (in a..d)
enum class SilenceAction : std::uint8_t {
    TakingOverHot,          // from the fresh mirror: no INIT, the slaves stay where they are
    TakingOverCold,         // no fresh mirror: the slaves start over from INIT
    RefusedForced,          // forced to standby: never takes over
    RefusedPartnerDiffers,  // the silent partner ran another ENI or other pair parameters
    RefusedIsolated,        // both own links are down
};
enum class HandOffPhase : std::uint8_t {
    Announced,     // ACTIVE: the hand-off is in the CMF, for cycle b
    Acknowledged,  // ACTIVE: the partner will take over at cycle b
    SteppedDown,   // ACTIVE: sent its last cycle, now INACTIVE
    TakenOver,     // INACTIVE: took over at cycle b as announced
    Cancelled,     // either side: the hand-off did not happen (c says why)
    Refused,       // not started (c says why)
};
enum class HandOffRefusal : std::uint8_t {
    None,
    PartnerNotAnswering,  // no standby status came back from the partner lately
    PartnerCold,          // the partner does not mirror this master (not fresh)
    PartnerForced,        // the partner is forced to standby
    PartnerDiffers,       // the partner runs another ENI or other pair parameters
    PartnerLinkDown,      // one of the partner's links is down
    NotAcknowledged,      // the partner did not acknowledge in time
    NotActive,            // this master is not ACTIVE and its partner did not hand off
    AlreadyRunning,       // a hand-off is under way
    PartnerLost,          // the partner went silent during the hand-off
    ForcedStandby,        // this master was forced to standby while it was to take over
};
// "the partner is forced to standby" (for events and operator replies).
std::string_view to_string(HandOffRefusal refusal);

enum class BackoffCode : std::uint8_t { Random = 0, Preferred = 1, Deferring = 2 };
enum class RuleCode : std::uint8_t { SlavesReached = 0, Epoch = 1, Mac = 2, None = 3 };
enum class ArbitrationOutcome : std::uint8_t {
    TookBusAfterListening,  // start-up: no ACTIVE heard
    YieldedToActive,        // start-up or backoff: an ACTIVE was heard
    KeptBusAfterCollision,  // backoff over in silence: this master owns the bus
};
enum class NoActiveReason : std::uint8_t {
    ForcedStandby,   // this member is forced to standby and no ACTIVE partner is heard
    PartnerDiffers,  // the only master heard runs another ENI / other parameters, and is silent now
    Isolated,        // both own links are down
};

// How a Hot-Connect topology change ended (TopologyChangeDone, DetectAddGroups, ProbeAllGroups: a).
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

// Why a port's loop setting changed (EventKind::PortLoopChanged, d).
inline constexpr std::uint32_t kPortByOperator = 0;
inline constexpr std::uint32_t kPortBorderClose = 1;
inline constexpr std::uint32_t kPortBlockNode = 2;
inline constexpr std::uint32_t kPortOpenBlocked = 3;

// What differs from a redundant partner (EventKind::PartnerMismatch, a).
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

enum class FrameResponseReason : std::uint8_t { ForeignSourceMac = 1, Malformed = 2, LateOrStale = 3 };

std::string_view to_string(EventKind kind);

struct Event {
    EventKind kind = EventKind::MasterStateChanged;
    std::uint64_t cycle = 0;
    std::chrono::system_clock::time_point time;
    std::uint32_t a = 0, b = 0, c = 0, d = 0;
};

// What a FrameLost event says about the frame (packed into c and d):
// which copies were sent and came back, the state a cyclic frame was built
// for, the first datagram of an acyclic frame (command, address, length)
// and how many it carried.
struct LostFrameDetail {
    std::uint8_t master_state = 0;  // cyclic: AL state code (eni::SlaveState), in d
    wire::Command first_command = wire::Command::Nop;
    std::uint8_t datagrams = 0;
    std::uint16_t first_length = 0;  // at most 1486 (11 bits)
    std::uint32_t first_address = 0; // acyclic: ADP | ADO << 16, or the logical address, in d
    bool sent_main = false;
    bool sent_red = false;
    bool main_returned = false;  // a copy came back, but the frame was still incomplete
    bool red_returned = false;

    void encode_into(Event& event) const;  // event.a (the frame kind) must be set
    static LostFrameDetail decode(const Event& event);
    std::string copies_text() const;  // "MAIN copy missing, RED copy came back"
};

// One line for logs and operators ("cycle 123: line break after slave 2"),
// from the event alone; EventDescriber says more.
std::string describe(const Event& event);

// What a CoeEmergency event says about the emergency: "CoE emergency 0x8130
// (communication), error register 0x11, data 01 02 03 04 05".
std::string coe_emergency_text(const Event& event);

// A bounded multi-producer queue: producers never wait for the consumer
// (the lock is held only to copy one event), a full queue drops and counts.
class EventQueue {
public:
    explicit EventQueue(std::size_t capacity = 1024);

    void push(const Event& event);
    // For producers outside the cycle thread (state machine, slave monitor,
    // topology verifier, mirror): stamps the time and the current cycle of
    // the attached counter (0 when none is attached).
    void raise(EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0, std::uint32_t d = 0);
    // The master's cycle counter; nullptr detaches it. The counter must
    // outlive the attachment.
    void attach_cycle_counter(const std::atomic<std::uint64_t>* counter);
    // Waits up to `timeout` for events; returns what is queued (possibly nothing).
    std::vector<Event> pop_all(std::chrono::milliseconds timeout);
    std::uint64_t dropped() const;

private:
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::vector<Event> ring_;
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint64_t dropped_ = 0;
    std::atomic<const std::atomic<std::uint64_t>*> cycle_counter_{nullptr};
};

}  // namespace ecpair::master
