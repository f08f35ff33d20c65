#pragma once
// The time control loop of an ESC (datasheet I §9.1.3.3, II §2.15.2): what a
// write of the reference time to 0x0910 (ARMW/FRMW, or the master's own
// time) does to the local clock.
//
// Each received time gives one difference, in the lower 32 bits as the
// datasheet says:  Δt = (local copy of the system time at the frame's start
// - system time delay) - received time.  Positive: this clock is ahead. The
// loop then, as ecsim models it:
//
//  - speed counter diff (0x0932, D): one step per received time towards
//    slowing down a clock that is ahead (D + 1) or speeding up one that is
//    behind (D - 1), within +-(speed counter start - 0x7F). The clock's rate
//    is the oscillator's times (1 - deviation(D)), with the datasheet's
//    relation  deviation = D / (5 (S + D + 2) (S - D + 2))  for S = speed
//    counter start (0x0930): about 0.012 ppm a step and +-763 ppm at most
//    with the reset value 0x1000; a larger S, smaller steps (a smaller
//    bandwidth, a smoother adjustment). This is the slow part: a 100 ppm
//    difference takes ~3 250 received times, which is why masters send a
//    burst of thousands of them at start-up ("static drift compensation");
//  - a phase correction: a quarter of Δt is slewed out over the interval
//    the previous received time came before this one (so the correction is
//    done by the time the next one is due, whatever the master's period),
//    within the same rate limit. The first received time after a reset has
//    no interval yet and only steps D;
//  - system time difference (0x092C): the mean of Δt, an exponential mean of
//    depth 0x0934 (2^-depth of each new value; 0: the last Δt), as sign and
//    magnitude: bit 31 set when the local copy is smaller than the received
//    time (the facts sheet; the ESC-integrating MCUs' register descriptions
//    say the same), bits 30:0 |Δt| up to 0x7FFFFFFF;
//  - a write to 0x0930 resets the filters, D and 0x092C (section II 2.15.2.5;
//    the ET1100 resets nothing on a write of 0x0934/0x0935). Values outside
//    0x0080..0x3FFF are taken as the nearest valid one.
//  - Δt beyond +-2^30 ns is outside what the datasheet calls stable: it is
//    taken as +-2^30, so the clock slews at the rate limit.
//
// The speed counter filter depth (0x0935) is a plain register here: ecsim
// models the loop as with depth 0, which the datasheet recommends. The real
// ESC's internal filters are not documented; this model keeps what a master
// can see: the registers, the rate limit, the D resolution, and a clock that
// settles on the reference when the master does what the datasheet says.

#include <cstdint>
#include <optional>

#include "dc_clock.hpp"
#include "esc_memory.hpp"

namespace ecpair::sim {

// How the clock runs from a received time on (LocalClock::set_rate).
struct ClockAdjustment {
    ClockRate rate = kNominalRate;
    std::uint64_t until = 0;  // the slew ends here
    ClockRate rate_after = kNominalRate;
};

class TimeLoop {
public:
    explicit TimeLoop(EscMemory& memory);

    // Power-on: no history, D = 0, 0x092C and 0x0932 zero.
    void reset();
    // A write to 0x0930: the same, the registers as the master left them.
    void restart() { reset(); }

    // One received time: `difference` is Δt (above), taken at common time `t`
    // for an ESC whose oscillator runs at `oscillator`.
    ClockAdjustment on_received_time(std::uint64_t t, std::int32_t difference, ClockRate oscillator);
    // The rate with D's correction and no phase slew.
    ClockRate steady_rate(ClockRate oscillator) const;


private:
    std::int32_t speed_counter_start() const;
    // deviation(D) as a fraction of 2^32.
    static std::int64_t deviation_q32(std::int32_t start, std::int32_t diff);
    void publish();

    EscMemory& memory_;
    std::int32_t diff_ = 0;               // D
    std::int64_t mean_q8_ = 0;            // the mean Δt in 2^-8 ns
    std::optional<std::uint64_t> last_t_;  // when the previous received time came
};

}  // namespace ecpair::sim
