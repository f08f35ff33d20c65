#pragma once
// The master's own events (design.md §5): what its cycle, its links, its
// state machine, its bus scans and its slave monitor report, with the names
// EtherCAT users know from commercial masters. The numbers each carries are
// listed with its kind; master_events.cpp describes them, naming slaves,
// frames and datagrams through the EventDescriber. The layers above the
// master own their events in their own folders (docs/ARCHITECTURE.md).

#include <cstdint>
#include <string>

#include "ecpair/master/event.hpp"
#include "ecpair/wire/command.hpp"

namespace ecpair::master::events {

extern const EventType kMasterStateChanged;   // a = from state, b = to state
// a = frame, b = datagram index (in the plan's frame), c = expected, d = received. Repeats per cycle: summarised
// per datagram.
extern const EventType kCyclicWkcError;
// a = frame kind, b = frame index (cyclic) / batch (acyclic), c and d: LostFrameDetail. Repeats per cycle:
// summarised per cyclic frame, acyclic frames together.
extern const EventType kFrameLost;
extern const EventType kLineBreak;            // a = slaves reachable from MAIN (break after that position), b = 1 if known
extern const EventType kLineRepaired;
extern const EventType kLinkDown;             // a = link role
extern const EventType kLinkUp;               // a = link role
extern const EventType kBusScanStatus;        // a = slaves found, b = slaves configured, c = 1 if the bus matches
extern const EventType kBusMismatch;          // a = position (from 0), b = mismatch kind (bus::SlaveMatch)
extern const EventType kBusMismatchIdentification;  // a = position, b = identification Ado, c = value read (0x10000: none), d = expected
extern const EventType kBusMismatchPlace;     // a = position, b = previous station, c = previous port (0..3), d = previous position
extern const EventType kSlavePresence;        // a = slave index (ENI order, from 0), b = 1 present / 0 absent
extern const EventType kSlaveStateError;      // a = slave index, b = AL status, c = AL status code
extern const EventType kSlaveIdentificationUpdated;  // a = slave index, b = the station alias now (ETG.1020 code 0x0061)
extern const EventType kTransitionFailed;     // a = from state, b = to state, c = slave index or 0xFFFF for the master
// a = reason (FrameResponseReason), b = link role; at most one a cycle. Repeats: summarised per reason and link.
extern const EventType kFrameResponseError;
extern const EventType kTopologyChangeDetected;  // a = slaves counted before, b = now (0xFFFF: not known), from the cycle
// The cycle thread (CycleThread's stall): a = µs it woke after its deadline, b = deadlines skipped. Summarised.
extern const EventType kCycleStall;
// A slave's CoE emergency (the mailbox service): a = slave index, b = error code | error register << 16,
// c = data bytes 0-3 (little-endian), d = data byte 4. Summarised per slave and error code: a slave that
// keeps sending emergencies is reported at its first, once a second with counts, and when it stops.
extern const EventType kCoeEmergency;

}  // namespace ecpair::master::events

namespace ecpair::master {

enum class FrameResponseReason : std::uint8_t { ForeignSourceMac = 1, Malformed = 2, LateOrStale = 3 };

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

}  // namespace ecpair::master
