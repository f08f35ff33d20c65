#pragma once
// The cyclic unit of an ESC: SYNC0/SYNC1 generation (datasheet I §9.2.3,
// II §2.15.3-2.15.4), computed from the local copy of the system time.
//
// Registers:
//   0x0980 b0        cyclic unit control: 1 = PDI-controlled, ECAT writes to
//                    0x0981, 0x0990 and 0x09A0-0x09A7 are then ignored
//   0x0981           activation: b0 cyclic unit, b1 SYNC0, b2 SYNC1,
//                    b3 auto-activation by a start time write, b4 extension
//                    of a 32-bit start time to 64 bits, b5 start time
//                    plausibility check, b6 near future = ~2.1 s (else half
//                    the DC width), b7 one debug pulse (self-clearing)
//   0x0982           pulse length in 10 ns (from the SII; 0: acknowledge mode)
//   0x0984           activation status: b0 first SYNC0 pulse pending, b1 first
//                    SYNC1 pulse pending, b2 the start time was outside the
//                    near future at activation
//   0x098E / 0x098F  SYNC0 / SYNC1 status (the signal: within its pulse; in
//                    acknowledge mode set from the first pulse on, as nothing
//                    on ecsim's PDI side acknowledges it)
//   0x0990           write: start time; read: the next SYNC0 pulse while the
//                    unit runs, the start time written otherwise
//   0x0998           next SYNC1 pulse
//   0x09A0 / 0x09A4  SYNC0 cycle time (0: single shot) / SYNC1 "cycle time":
//                    SYNC1 follows a SYNC0 pulse by that much, and only the
//                    first SYNC0 pulse at or after the previous SYNC1 starts
//                    the next one (0: SYNC1 is SYNC0)
//
// Activation (b0 0 -> 1, or auto-activation) takes the start time: a start
// time in the future starts the pulses there; one in the past is never
// reached by a 64-bit DC and reached after the 32-bit turn-over by a 32-bit
// one, unless the plausibility check is on: then a start time outside the
// near future gives a pulse at once and the pulses go on on the start
// time's grid.
//
// The unit works in the unwrapped 64-bit system time of its DcUnit (for a
// 32-bit DC the upper half counts turn-overs); a pulse with nominal system
// time S happens at the first common time the system time reaches S, found
// with LocalClock::common_time_of(). advance() takes the pulses up to a
// common time and is called before every change of the clock, so a clock
// that jumps forward (a new offset) fires the pulses it skipped at the
// moment of the jump, as one pulse. For each slave the unit counts, while
// SYNC0 runs, pulses that came less than half a cycle after the previous
// one (doubled), and missed edges: those a forward jump skipped (a pulse
// whose nominal system time is more than a cycle after the previous one's)
// and cycles of the common time base without a pulse (a jump back, a stall).

#include <cstdint>
#include <optional>

#include "dc_clock.hpp"
#include "ecpair/sim/esc.hpp"
#include "esc_memory.hpp"

namespace ecpair::sim {

// The system time as the unit sees it: sys(t) = clock.local_at(t) + offset.
struct SystemTimeBase {
    const LocalClock* clock = nullptr;
    std::uint64_t offset = 0;  // unwrapped

    std::uint64_t at(std::uint64_t t) const { return clock->local_at(t) + offset; }
    std::uint64_t when(std::uint64_t system_ns) const { return clock->common_time_of(system_ns - offset); }
};

// Which of the unit's registers a frame wrote.
struct SyncWrites {
    bool control = false;
    bool activation = false;
    bool start_low = false;   // 0x0990-0x0993 (auto-activation: 0x0993)
    bool start_high = false;  // 0x0994-0x0997 (auto-activation of a 64-bit DC: 0x0997)
    bool cycle_times = false;
    bool any() const { return control || activation || start_low || start_high || cycle_times; }
};

class SyncUnit {
public:
    SyncUnit(EscMemory& memory, int width_bits);

    void reset();
    // Drops the ECAT writes a PDI-controlled unit ignores (before the frame's writes are committed).
    void filter_staged() const;
    // The pulses up to common time `t`, with the clock as it runs now.
    void advance(std::uint64_t t, const SystemTimeBase& base);
    // After the frame at `t` committed writes to the unit's registers.
    void on_written(std::uint64_t t, const SystemTimeBase& base, const SyncWrites& writes);
    // 0x0984, 0x098E/F, 0x0990, 0x0998 as a read at `t` sees them.
    void refresh_registers(std::uint64_t t, const SystemTimeBase& base);

    // SYNC0 is being generated (cyclic unit and SYNC0 activated).
    bool sync0_running() const { return active_ && sync0_; }
    const std::optional<SyncEdge>& last_pulse() const { return last_; }
    const std::optional<SyncEdge>& previous_pulse() const { return previous_; }
    std::uint32_t cycle_ns() const { return cycle0_; }
    std::uint64_t missed() const { return missed_; }
    std::uint64_t doubled() const { return doubled_; }
    void reset_counters() { missed_ = doubled_ = 0; }

private:
    void activate(std::uint64_t t, const SystemTimeBase& base);
    void deactivate();
    // A pulse at common time `at`: counted against the one before it.
    void pulse(std::uint64_t system_ns, std::uint64_t at);
    std::uint64_t width_mask() const;
    // The first value >= sys with these low bits (the next turn-over of a 32-bit DC).
    std::uint64_t next_occurrence(std::uint64_t low, std::uint64_t sys) const;
    std::optional<std::uint64_t> next_sync1(std::uint64_t sys) const;
    std::optional<std::uint64_t> last_sync1(std::uint64_t sys) const;

    EscMemory& memory_;
    int width_bits_;

    bool active_ = false;  // 0x0981 b0
    bool sync0_ = false;   // b1
    bool sync1_ = false;   // b2
    std::uint64_t start_written_ = 0;  // 0x0990 as written (register width)
    std::uint64_t start_ = 0;          // the start time in the unit's unwrapped system time
    std::uint32_t cycle0_ = 0;
    std::uint32_t cycle1_ = 0;
    std::uint64_t next_ = 0;           // nominal system time of the next pulse
    bool never_ = false;               // a 64-bit start time in the past: no pulse
    bool done_ = false;                // single shot fired
    bool out_of_near_future_ = false;  // 0x0984 b2
    std::uint64_t advanced_to_ = 0;

    std::optional<SyncEdge> last_;
    std::optional<SyncEdge> previous_;
    bool chained_ = false;  // last_ is this activation's: the next pulse is counted against it
    std::uint64_t missed_ = 0;
    std::uint64_t doubled_ = 0;
};

}  // namespace ecpair::sim
