#pragma once
// The distributed clocks unit of one ESC (datasheet I §9, II §2.15,
// dc-and-diagnosis-facts.md): its local clock, the registers a master reads
// and writes, and what ecsim reports as the truth about it.
//
//  - local clock: its own oscillator (drift in ppb, set by the segment) and
//    a local time that starts at power-on wherever the segment says
//    (dc_clock.hpp); the time control loop changes its rate
//    (dc_time_loop.hpp);
//  - 0x0900-0x090F receive time port 0-3: a frame that writes 0x0900 with
//    BWR or FPWR latches, for itself, the local time at which it arrived at
//    each port it passed, before or after the processing unit (the segment
//    reports every arrival); 0x0918 (64 bit) the local time at which it
//    reached the processing unit, for any write to 0x0900. A write that does
//    not latch (APWR, say) leaves them alone; the values are there for the
//    next frame;
//  - 0x0910 read: the local copy of the system time when the frame passed the
//    reference clock: local time at the frame's start + offset (0x0920) -
//    system time delay (0x0928); write: the received time for the loop,
//    compared at the end of the frame, never stored;
//  - 0x0920 offset and 0x0928 delay are taken at the end of the frame that
//    writes them: the system time jumps, the local time does not;
//  - the cyclic unit (dc_sync_unit.hpp).
//
// DC support as the ESC's description says: none (2-port slaves need not
// have DC: every DC register then reads 0 and ignores writes, which still
// count for the working counter), 32-bit (the system time, offset, start
// time and next SYNC1 are 32 bits wide; receive time 0x0918 stays 64) or
// 64-bit.

#include <array>
#include <cstdint>
#include <optional>

#include "dc_clock.hpp"
#include "dc_sync_unit.hpp"
#include "dc_time_loop.hpp"
#include "ecpair/sim/esc.hpp"
#include "esc_memory.hpp"
#include "physical_access.hpp"

namespace ecpair::sim {

// What the datagrams of one frame did to this ESC's DC unit (DatagramProcessor).
struct DcFrameAccess {
    bool port_latch = false;      // a BWR or FPWR wrote 0x0900: the ports' receive times latch
    bool reference_read = false;  // an ARMW/FRMW read 0x0910 here: the master uses this ESC as reference clock
};

class DcUnit final : public ComputedRegisters {
public:
    DcUnit(EscMemory& memory, DcSupport support);

    DcSupport support() const { return support_; }
    bool has_system_time() const { return support_ != DcSupport::None; }

    // The oscillator; the local time starts again as at the last power-on.
    void set_oscillator(const Oscillator& oscillator);
    // Power-on at common time `now_ns`: the local time starts where the
    // oscillator says, registers and loop are reset. The truth counters survive.
    void power_on(std::uint64_t now_ns);

    // ---- the frame path
    // Before the frame's writes are committed: drops those the unit ignores.
    void filter_staged() const;
    // The frame reached the processing unit at common time `t`.
    void start_of_frame(std::uint64_t t) { frame_start_ = t; }
    void before_read(std::uint32_t begin, std::uint32_t end) override;
    // A frame reached `port` from outside.
    void port_arrival(int port, std::uint64_t time_ns, std::uint64_t frame_seq);
    // After the frame's writes were committed.
    void end_of_frame(std::uint64_t frame_seq, const DcFrameAccess& access);

    // ---- the truth (ecsim's dc report)
    // The local copy of the system time at common time `t`, unwrapped (a
    // 32-bit DC's register shows the low half).
    std::uint64_t system_time_at(std::uint64_t t) const { return base().at(t); }
    std::uint64_t local_time_at(std::uint64_t t) const { return clock_.local_at(t); }
    std::int64_t drift_ppb() const { return oscillator_spec_.drift_ppb; }
    // The pulses up to `t` (no register changes).
    void advance_sync(std::uint64_t t) { sync_.advance(t, base()); }
    const SyncUnit& sync() const { return sync_; }
    void reset_sync_counters() { sync_.reset_counters(); }
    // Every change that moves this ESC's system time against the others'
    // (rate, jump, SYNC0 started or stopped) is a step; last_step() is the
    // latest. Reference reads: ARMW/FRMW reads of 0x0910 here.
    DcCounters counters() const {
        DcCounters counters = counters_;
        counters.sync0_running = sync_.sync0_running();
        return counters;
    }
    const DcClockStep& last_step() const { return last_step_; }

private:
    struct Arrival {
        std::uint64_t time_ns = 0;
        std::uint64_t frame_seq = 0;
        bool valid = false;
    };

    SystemTimeBase base() const { return SystemTimeBase{&clock_, offset_}; }
    void latch_port(int port, std::uint64_t time_ns);
    void latch_receive_times(std::uint64_t frame_seq, bool ports);
    // 0x0910 was written: the received time feeds the loop.
    void compare_received_time();
    void apply_offset();
    // The local time at the power-on numbered `power_on` (0: the first).
    std::uint64_t start_local_time(std::uint64_t power_on) const;
    void step(std::uint64_t before, bool sync0_before);

    EscMemory& memory_;
    DcSupport support_;
    LocalClock clock_;
    TimeLoop loop_;
    SyncUnit sync_;
    Oscillator oscillator_spec_;
    ClockRate oscillator_ = kNominalRate;
    std::uint64_t power_on_at_ = 0;
    std::uint64_t power_ons_ = 0;
    std::uint64_t offset_ = 0;  // applied 0x0920, unwrapped
    std::uint32_t delay_ = 0;   // applied 0x0928
    std::uint64_t frame_start_ = 0;
    std::array<Arrival, kMaxPorts> arrivals_{};
    std::uint64_t latch_seq_ = 0;
    bool latch_pending_ = false;  // ports after the processing unit still latch for latch_seq_

    DcCounters counters_;
    DcClockStep last_step_;
};

}  // namespace ecpair::sim
