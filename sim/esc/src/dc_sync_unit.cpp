// advance() computes a batch of pulses at once: the first (which, after a
// forward jump of the clock, gathers every pulse the jump skipped into one
// at the jump), the second, and the last two. The pulses in between lie on
// one continuous clock and are one cycle apart by construction, so only the
// first two of a batch are counted against their predecessor.

#include "dc_sync_unit.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint8_t kActivate = 0x01;
constexpr std::uint8_t kSync0 = 0x02;
constexpr std::uint8_t kSync1 = 0x04;
constexpr std::uint8_t kAutoActivation = 0x08;
constexpr std::uint8_t kExtension = 0x10;
constexpr std::uint8_t kPlausibilityCheck = 0x20;
constexpr std::uint8_t kShortNearFuture = 0x40;
constexpr std::uint8_t kDebugPulse = 0x80;
constexpr std::uint64_t kShortNearFutureNs = std::uint64_t{1} << 31;  // "~2.1 s"
constexpr std::uint64_t kPulseUnitNs = 10;

// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

}  // namespace

SyncUnit::SyncUnit(EscMemory& memory, int width_bits) : memory_(memory), width_bits_(width_bits) {}

void SyncUnit::reset() {
    active_ = sync0_ = sync1_ = false;
    start_written_ = start_ = next_ = 0;
    cycle0_ = cycle1_ = 0;
    never_ = done_ = out_of_near_future_ = false;
    advanced_to_ = 0;
    last_.reset();
    previous_.reset();
    chained_ = false;
}

std::uint64_t SyncUnit::width_mask() const {
    return width_bits_ >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width_bits_) - 1;
}

std::uint64_t SyncUnit::next_occurrence(std::uint64_t low, std::uint64_t sys) const {
    return sys + ((low - sys) & width_mask());
}

void SyncUnit::filter_staged() const {
    if ((memory_.u8(reg::kDcCycleUnitControl) & 0x01) == 0) return;  // ECAT-controlled
    memory_.discard_staged(reg::kDcActivation, reg::kDcActivation + 1);
    memory_.discard_staged(reg::kDcStartTime, reg::kDcStartTime + 8);
    memory_.discard_staged(reg::kDcCycleTime0, reg::kDcCycleTime1 + 4);
}

void SyncUnit::pulse(std::uint64_t system_ns, std::uint64_t at) {
    if (chained_ && last_ && cycle0_ != 0) {
        // Nominal edges a forward jump of the clock skipped (fired together in one pulse) ...
        const std::uint64_t edges = (system_ns - last_->system_ns) / cycle0_;
        if (edges >= 2) missed_ += edges - 1;
        // ... and, on the common time base, cycles without a pulse or a pulse too soon.
        const std::uint64_t interval = at - last_->at_ns;
        const std::uint64_t cycles = (interval + cycle0_ / 2) / cycle0_;
        if (cycles == 0) ++doubled_;
        if (cycles >= 2) missed_ += cycles - 1;
    }
    previous_ = last_;
    last_ = SyncEdge{system_ns, at};
    chained_ = true;
}

void SyncUnit::advance(std::uint64_t t, const SystemTimeBase& base) {
    if (static_cast<std::int64_t>(t - advanced_to_) <= 0) return;  // time does not run backwards here
    const std::uint64_t from = advanced_to_;
    advanced_to_ = t;
    if (!active_ || never_ || done_) return;
    const std::uint64_t sys = base.at(t);
    if (static_cast<std::int64_t>(sys - next_) < 0) return;
    if (cycle0_ == 0) {
        if (sync0_) pulse(next_, std::max(base.when(next_), from));
        done_ = true;
        return;
    }
    // Pulses next_, next_ + c, ... up to sys. Those the clock had passed by
    // `from` (a jump) fire together at `from`.
    const std::uint64_t count = (sys - next_) / cycle0_ + 1;
    const std::uint64_t last = next_ + (count - 1) * cycle0_;
    std::uint64_t first = next_;
    const std::uint64_t sys_from = base.at(from);
    if (static_cast<std::int64_t>(sys_from - next_) >= 0) {
        const std::uint64_t skipped = std::min<std::uint64_t>((sys_from - next_) / cycle0_ + 1, count);
        first = next_ + (skipped - 1) * cycle0_;
    }
    next_ = last + cycle0_;
    if (!sync0_) return;
    pulse(first, std::max(base.when(first), from));
    if (first == last) return;
    const std::uint64_t second = first + cycle0_;
    pulse(second, std::max(base.when(second), from));
    if (second == last) return;
    // The rest are one cycle apart: only the last two are kept.
    const std::uint64_t before_last = last - cycle0_;
    previous_ = before_last == second ? last_ : std::optional(SyncEdge{before_last, base.when(before_last)});
    last_ = SyncEdge{last, base.when(last)};
}

void SyncUnit::activate(std::uint64_t t, const SystemTimeBase& base) {
    active_ = true;
    never_ = done_ = false;
    chained_ = false;
    const std::uint8_t activation = memory_.u8(reg::kDcActivation);
    const std::uint64_t sys = base.at(t);
    const std::uint64_t ahead = (start_ - sys) & width_mask();
    const std::uint64_t near_future =
        (activation & kShortNearFuture) != 0 ? kShortNearFutureNs : (width_mask() >> 1) + 1;
    out_of_near_future_ = ahead >= near_future;
    if ((activation & kPlausibilityCheck) != 0 && out_of_near_future_) {
        // At once, then on the start time's grid.
        if (sync0_) pulse(sys, t);
        if (cycle0_ == 0) {
            done_ = true;
            return;
        }
        const std::int64_t k = floor_div(static_cast<std::int64_t>(sys - start_), cycle0_) + 1;
        next_ = start_ + static_cast<std::uint64_t>(k) * cycle0_;
        return;
    }
    if (width_bits_ >= 64 && ahead >= (width_mask() >> 1) + 1) {
        never_ = true;  // in the past: a 64-bit DC waits "hundreds of years"
        return;
    }
    next_ = sys + ahead;
}

void SyncUnit::deactivate() {
    active_ = false;
    chained_ = false;
}

void SyncUnit::on_written(std::uint64_t t, const SystemTimeBase& base, const SyncWrites& writes) {
    advance(t, base);
    std::uint8_t activation = memory_.u8(reg::kDcActivation);
    if (writes.cycle_times) {
        // A running unit keeps its next pulse; the ones after it follow the new cycle.
        cycle0_ = memory_.load<std::uint32_t>(reg::kDcCycleTime0);
        cycle1_ = memory_.load<std::uint32_t>(reg::kDcCycleTime1);
    }
    bool auto_activate = false;
    if (writes.start_low || writes.start_high) {
        std::uint64_t written = memory_.load<std::uint64_t>(reg::kDcStartTime) & width_mask();
        const bool extend = width_bits_ < 64 || ((activation & kExtension) != 0 && !writes.start_high);
        if (width_bits_ < 64) {
            memory_.store<std::uint32_t>(reg::kDcStartTime + 4, 0);  // not implemented in a 32-bit DC
        }
        const std::uint64_t sys = base.at(t);
        start_ = extend ? next_occurrence(written & 0xFFFFFFFFU, sys) : written;
        if (extend && width_bits_ >= 64) written = start_;
        start_written_ = written;
        if ((activation & kAutoActivation) != 0) {
            auto_activate = extend ? writes.start_low : writes.start_high;
        }
    }
    if (auto_activate && (activation & kActivate) == 0) {
        activation = static_cast<std::uint8_t>(activation | kActivate);
        memory_.set_u8(reg::kDcActivation, activation);
    }
    const bool sync0_before = sync0_;
    sync0_ = (activation & kSync0) != 0;
    sync1_ = (activation & kSync1) != 0;
    if (sync0_ != sync0_before) chained_ = false;
    const bool activate_now = (activation & kActivate) != 0;
    if (activate_now && (!active_ || auto_activate)) activate(t, base);
    if (!activate_now && active_) deactivate();
    if ((activation & kDebugPulse) != 0) {
        if (sync0_) pulse(base.at(t), t);
        memory_.set_u8(reg::kDcActivation, static_cast<std::uint8_t>(activation & ~kDebugPulse));
    }
}

std::optional<std::uint64_t> SyncUnit::next_sync1(std::uint64_t sys) const {
    if (!active_ || never_) return std::nullopt;
    if (cycle0_ == 0) {
        const std::uint64_t only = start_ + cycle1_;
        return static_cast<std::int64_t>(only - sys) > 0 ? std::optional(only) : std::nullopt;
    }
    const std::uint64_t stride = std::max<std::uint64_t>(1, (cycle1_ + cycle0_ - 1) / cycle0_) * cycle0_;
    const std::int64_t since = static_cast<std::int64_t>(sys - start_ - cycle1_);
    if (since < 0) return start_ + cycle1_;
    return start_ + cycle1_ + (static_cast<std::uint64_t>(since) / stride + 1) * stride;
}

std::optional<std::uint64_t> SyncUnit::last_sync1(std::uint64_t sys) const {
    if (!active_ || never_) return std::nullopt;
    const std::int64_t since = static_cast<std::int64_t>(sys - start_ - cycle1_);
    if (since < 0) return std::nullopt;
    if (cycle0_ == 0) return start_ + cycle1_;
    const std::uint64_t stride = std::max<std::uint64_t>(1, (cycle1_ + cycle0_ - 1) / cycle0_) * cycle0_;
    return start_ + cycle1_ + (static_cast<std::uint64_t>(since) / stride) * stride;
}

void SyncUnit::refresh_registers(std::uint64_t t, const SystemTimeBase& base) {
    advance(t, base);
    const std::uint64_t sys = base.at(t);
    const std::uint64_t pulse_ns = memory_.load<std::uint16_t>(regs::kDcSyncPulseLength) * kPulseUnitNs;
    const bool acknowledge_mode = pulse_ns == 0;
    const bool first_pending = active_ && sync0_ && !done_ && (never_ || !chained_);
    const auto sync1_last = sync1_ ? last_sync1(sys) : std::nullopt;
    std::uint8_t status = 0;
    if (first_pending) status |= 0x01;
    if (active_ && sync1_ && !sync1_last) status |= 0x02;
    if (active_ && out_of_near_future_) status |= 0x04;
    memory_.set_u8(regs::kDcActivationStatus, status);

    const auto signal = [&](std::optional<std::uint64_t> pulse_at) {
        if (!pulse_at) return std::uint8_t{0};
        if (acknowledge_mode) return std::uint8_t{1};
        return static_cast<std::uint8_t>(sys - *pulse_at < pulse_ns ? 1 : 0);
    };
    const bool sync0_pulsed = sync0_running() && chained_ && last_;
    memory_.set_u8(regs::kDcSync0Status, signal(sync0_pulsed ? std::optional(last_->system_ns) : std::nullopt));
    memory_.set_u8(regs::kDcSync1Status, signal(sync1_last));

    const std::uint64_t mask = width_mask();
    const std::uint64_t start_view = active_ && !never_ && !done_ ? next_ & mask : start_written_;
    memory_.store<std::uint64_t>(reg::kDcStartTime, start_view);
    const auto sync1_next = sync1_ ? next_sync1(sys) : std::nullopt;
    memory_.store<std::uint64_t>(regs::kDcNextSync1, sync1_next ? *sync1_next & mask : 0);
}

}  // namespace ecpair::sim
