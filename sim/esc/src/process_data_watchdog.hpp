#pragma once
// The ESC's process data watchdog (datasheet I "Watchdogs", esc-facts.md §2):
// every ECAT write to the buffer of a SyncManager whose control byte has the
// watchdog trigger (0x0804 + 8n b6) restarts it; when no such write came for
// 0x0420 ticks of (0x0400 + 2) x 40 ns (after reset 1000 x 100 us = 100 ms)
// it expires.
//
//  - 0x0440 b0: 1 while the watchdog runs or is disabled (0x0420 = 0),
//    0 when it expired or has not been triggered since power-on;
//  - 0x0442 counts the expiries (saturating, cleared by an ECAT write).
//
// What an expiry does to the slave is the owner's business (the ESC facade:
// digital outputs cleared; a slave stack in OP falls to SAFEOP+ERR 0x001B).
// The watchdog knows time only when told: each frame's time, and whatever
// the segment's timer passes to Esc::advance_time().

#include <cstdint>
#include <optional>

#include "esc_memory.hpp"

namespace ecpair::sim {

class ProcessDataWatchdog {
public:
    explicit ProcessDataWatchdog(EscMemory& memory);

    // Power-on: not triggered yet.
    void reset();
    // A write to a watched SyncManager buffer at `now_ns`.
    void trigger(std::uint64_t now_ns);
    // Expires the watchdog when its time passed by `now_ns`; true at the
    // moment it expires (once per expiry).
    bool advance(std::uint64_t now_ns);
    // When it will expire if nothing triggers it (nullopt: not running).
    std::optional<std::uint64_t> deadline() const { return deadline_ns_; }

private:
    std::uint64_t period_ns() const;
    void write_status();

    EscMemory& memory_;
    std::optional<std::uint64_t> deadline_ns_;
};

}  // namespace ecpair::sim
