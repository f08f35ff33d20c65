// The unit's order at the end of a frame: receive-time latches (with the
// clock as the frame found it), the comparison of a received time (with the
// system time latched at the frame's start, before this frame's offset or
// delay), then the offset, the delay and a loop reset, then the cyclic
// unit. Before anything changes the clock, the cyclic unit takes its pulses
// up to that moment with the clock as it was.

#include "dc_registers.hpp"

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint16_t kDcBegin = reg::kDcReceiveTimes;
constexpr std::uint16_t kDcEnd = 0x0A00;

}  // namespace

DcUnit::DcUnit(EscMemory& memory, DcSupport support)
    : memory_(memory), support_(support), loop_(memory), sync_(memory, support == DcSupport::Dc32 ? 32 : 64) {}

std::uint64_t DcUnit::start_local_time(std::uint64_t power_on) const {
    if (oscillator_spec_.start_seed == 0) return 0;
    // splitmix64 of seed and power-on: a different start at every power-on, the same in every run.
    std::uint64_t z = oscillator_spec_.start_seed + (power_on + 1) * 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return (z ^ (z >> 31)) & 0xFFFFFFFFU;
}

void DcUnit::set_oscillator(const Oscillator& oscillator) {
    oscillator_spec_ = oscillator;
    oscillator_ = rate_of_drift(oscillator.drift_ppb);
    clock_.start(power_on_at_, start_local_time(power_ons_ == 0 ? 0 : power_ons_ - 1), oscillator_);
}

void DcUnit::power_on(std::uint64_t now_ns) {
    clock_.start(now_ns, start_local_time(power_ons_), oscillator_);
    power_on_at_ = now_ns;
    ++power_ons_;
    frame_start_ = now_ns;
    offset_ = 0;
    delay_ = 0;
    arrivals_ = {};
    latch_pending_ = false;
    latch_seq_ = 0;
    loop_.reset();
    sync_.reset();
    if (!has_system_time()) {
        for (std::uint16_t a = kDcBegin; a < kDcEnd; ++a) memory_.set_u8(a, 0);  // reserved: reads 0
    }
    step(system_time_at(now_ns), false);
}

void DcUnit::step(std::uint64_t before, bool sync0_before) {
    ++counters_.steps;
    last_step_ = DcClockStep{frame_start_, before, system_time_at(frame_start_), sync0_before, sync_.sync0_running()};
}

void DcUnit::filter_staged() const {
    if (!has_system_time()) {
        memory_.discard_staged(kDcBegin, kDcEnd);
        return;
    }
    sync_.filter_staged();
    if (support_ == DcSupport::Dc32) {
        memory_.discard_staged(reg::kDcSystemTimeOffset + 4, reg::kDcSystemTimeOffset + 8);
        memory_.discard_staged(reg::kDcStartTime + 4, reg::kDcStartTime + 8);
    }
}

void DcUnit::before_read(std::uint32_t begin, std::uint32_t end) {
    if (!has_system_time()) return;
    if (regs::overlaps(begin, end, reg::kDcSystemTime, reg::kDcSystemTime + 8)) {
        // The local copy when the frame passed the reference clock.
        const std::uint64_t copy = system_time_at(frame_start_) - delay_;
        memory_.store<std::uint64_t>(reg::kDcSystemTime, support_ == DcSupport::Dc32 ? copy & 0xFFFFFFFFU : copy);
    }
    if (regs::overlaps(begin, end, regs::kDcActivationStatus, reg::kDcCycleTime0)) {
        sync_.refresh_registers(frame_start_, base());
    }
}

void DcUnit::port_arrival(int port, std::uint64_t time_ns, std::uint64_t frame_seq) {
    arrivals_[static_cast<std::size_t>(port)] = Arrival{time_ns, frame_seq, true};
    if (latch_pending_ && frame_seq == latch_seq_ && port != 0) latch_port(port, time_ns);
}

void DcUnit::latch_port(int port, std::uint64_t time_ns) {
    memory_.store<std::uint32_t>(static_cast<std::uint16_t>(reg::kDcReceiveTimes + 4 * port),
                                 static_cast<std::uint32_t>(clock_.local_at(time_ns)));
}

void DcUnit::latch_receive_times(std::uint64_t frame_seq, bool ports) {
    memory_.store<std::uint64_t>(reg::kDcReceiveTimeEcu, clock_.local_at(frame_start_));
    latch_pending_ = ports;
    latch_seq_ = frame_seq;
    if (!ports) return;
    // Port 0: where the frame arrived, or (port 0 closed) when it reached the processing unit.
    const Arrival& port0 = arrivals_[0];
    latch_port(0, port0.valid && port0.frame_seq == frame_seq ? port0.time_ns : frame_start_);
    // Ports the frame passed before the processing unit (it came in by another port).
    for (int p = 1; p < kMaxPorts; ++p) {
        const Arrival& a = arrivals_[static_cast<std::size_t>(p)];
        if (a.valid && a.frame_seq == frame_seq) latch_port(p, a.time_ns);
    }
}

void DcUnit::compare_received_time() {
    // The lower 32 bits of the received time; bytes the frame did not write
    // are the local copy's (only the written ones are compared).
    const std::uint64_t copy = system_time_at(frame_start_) - delay_;
    std::uint32_t received = 0;
    for (unsigned i = 0; i < 4; ++i) {
        const auto address = static_cast<std::uint16_t>(reg::kDcSystemTime + i);
        const std::uint32_t byte = memory_.staged(address) ? memory_.staged_value(address)
                                                           : static_cast<std::uint32_t>((copy >> (8 * i)) & 0xFF);
        received |= byte << (8 * i);
    }
    const auto difference = static_cast<std::int32_t>(static_cast<std::uint32_t>(copy) - received);
    sync_.advance(frame_start_, base());
    const ClockAdjustment adjustment = loop_.on_received_time(frame_start_, difference, oscillator_);
    clock_.set_rate(frame_start_, adjustment.rate, adjustment.until, adjustment.rate_after);
}

void DcUnit::apply_offset() {
    sync_.advance(frame_start_, base());
    const std::uint64_t written = memory_.load<std::uint64_t>(reg::kDcSystemTimeOffset);
    if (support_ == DcSupport::Dc32) {
        // Modulo 2^32: the smallest step that gives the written low half.
        offset_ += static_cast<std::uint64_t>(static_cast<std::int64_t>(
            static_cast<std::int32_t>(static_cast<std::uint32_t>(written) - static_cast<std::uint32_t>(offset_))));
    } else {
        offset_ = written;
    }
}

void DcUnit::end_of_frame(std::uint64_t frame_seq, const DcFrameAccess& access) {
    if (!has_system_time()) return;
    if (access.reference_read) ++counters_.reference_reads;
    if (!memory_.staged_any(kDcBegin, kDcEnd)) return;
    const std::uint64_t before = system_time_at(frame_start_);
    const bool was_running = sync_.sync0_running();
    bool changed = false;
    if (memory_.staged_any(reg::kDcReceiveTimes, reg::kDcReceiveTimes + 4)) {
        latch_receive_times(frame_seq, access.port_latch);
    }
    if (memory_.staged(reg::kDcSystemTime)) {
        compare_received_time();
        changed = true;
    }
    if (memory_.staged_any(reg::kDcSystemTimeOffset, reg::kDcSystemTimeOffset + 8)) {
        apply_offset();
        changed = true;
    }
    if (memory_.staged_any(reg::kDcSystemTimeDelay, reg::kDcSystemTimeDelay + 4)) {
        delay_ = memory_.load<std::uint32_t>(reg::kDcSystemTimeDelay);
    }
    if (memory_.staged_any(reg::kDcSpeedCounterStart, reg::kDcSpeedCounterStart + 2)) {
        sync_.advance(frame_start_, base());
        loop_.restart();
        clock_.set_rate(frame_start_, loop_.steady_rate(oscillator_), frame_start_, kNominalRate);
        changed = true;
    }
    SyncWrites writes;
    writes.control = memory_.staged(reg::kDcCycleUnitControl);
    writes.activation = memory_.staged(reg::kDcActivation);
    writes.start_low = memory_.staged_any(reg::kDcStartTime, reg::kDcStartTime + 4);
    writes.start_high = memory_.staged_any(reg::kDcStartTime + 4, reg::kDcStartTime + 8);
    writes.cycle_times = memory_.staged_any(reg::kDcCycleTime0, reg::kDcCycleTime1 + 4);
    if (writes.any()) sync_.on_written(frame_start_, base(), writes);
    if (changed || sync_.sync0_running() != was_running) step(before, was_running);
}

}  // namespace ecpair::sim
