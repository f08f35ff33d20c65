// Decisions are taken per channel for the part of the access that overlaps
// its buffer; the caller copies everything outside the refused ranges. With
// no active channel (or none overlapping) an access costs one mask test.

#include "sync_manager.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint16_t sm_register(std::size_t n, std::uint16_t offset) {
    return static_cast<std::uint16_t>(reg::kSmBase + n * reg::kSmSize + offset);
}

constexpr std::uint16_t kStatusOffset = 5;
constexpr std::uint16_t kActivateOffset = 6;
constexpr std::uint16_t kPdiControlOffset = 7;
constexpr std::uint8_t kRepeatBit = 0x02;
constexpr std::uint8_t kEcatIrqEnable = 0x10;

constexpr std::uint8_t bit(std::size_t n) { return static_cast<std::uint8_t>(1U << n); }

}  // namespace

SyncManagerUnit::SyncManagerUnit(EscMemory& memory) : memory_(memory) {}

void SyncManagerUnit::reset() {
    channels_ = {};
    states_ = {};
    activation_ = {};
    active_mask_ = 0;
    events_ = {};
    watchdog_triggered_ = false;
}

std::uint8_t SyncManagerUnit::refresh() {
    std::uint8_t activation_changed = 0;
    active_mask_ = 0;
    for (std::size_t n = 0; n < channels_.size(); ++n) {
        const auto config = wire::SyncManagerConfig::decode(memory_.bytes().subspan(sm_register(n, 0), reg::kSmSize));
        SmChannel next;
        next.start = config.physical_start;
        next.length = config.length;
        next.control = config.control;
        next.enabled = config.enabled();
        next.pdi_deactivated = (config.pdi_control & 0x01) != 0;
        const SmChannel& current = channels_[n];
        const bool reconfigured = next.start != current.start || next.length != current.length ||
                                  next.control != current.control || next.enabled != current.enabled;
        channels_[n] = next;
        if (reconfigured) reset_channel(n);
        if (config.activate != activation_[n]) activation_changed = static_cast<std::uint8_t>(activation_changed | bit(n));
        activation_[n] = config.activate;
        if (next.active()) active_mask_ = static_cast<std::uint8_t>(active_mask_ | bit(n));
    }
    return activation_changed;
}

SmAccessPlan SyncManagerUnit::plan_ecat_access(std::uint32_t address, std::size_t length, bool ecat_write) {
    SmAccessPlan plan;
    if (length == 0) return plan;
    const std::uint32_t begin = address;
    const auto end = static_cast<std::uint32_t>(address + length);
    if (active_mask_ != 0) {
        for (std::size_t n = 0; n < channels_.size(); ++n) {
            if ((active_mask_ & bit(n)) == 0) continue;
            const SmChannel& ch = channels_[n];
            if (ch.end() <= begin || ch.start >= end) continue;
            const std::uint32_t overlap_begin = std::max<std::uint32_t>(begin, ch.start);
            const std::uint32_t overlap_end = std::min(end, ch.end());
            const auto refuse = [&] { plan.refused[plan.refused_count++] = {overlap_begin, overlap_end}; };
            if (ch.pdi_deactivated) {
                refuse();
                continue;
            }
            if (ecat_write && ch.ecat_writes() && ch.watchdog_trigger()) watchdog_triggered_ = true;
            // A one-byte buffer and the other side's direction pass unmanaged.
            if (ch.length == 1 || ch.ecat_writes() != ecat_write) continue;
            State& state = states_[n];
            if (!ch.mailbox()) {
                if (overlap_end == ch.end()) complete(n, ecat_write);
                continue;
            }
            const bool buffer_ready = ecat_write ? !state.full : state.full;
            if (!buffer_ready || !(state.open || overlap_begin == ch.start)) {
                refuse();
                continue;
            }
            state.open = true;
            if (overlap_end == ch.end()) complete(n, ecat_write);
        }
    }
    std::sort(plan.refused.begin(), plan.refused.begin() + static_cast<std::ptrdiff_t>(plan.refused_count),
              [](const auto& a, const auto& b) { return a.begin < b.begin; });
    std::uint32_t cursor = begin;
    for (std::size_t i = 0; i < plan.refused_count && cursor < end; ++i) {
        if (plan.refused[i].begin > cursor) break;
        cursor = std::max(cursor, plan.refused[i].end);
    }
    plan.any_permitted = cursor < end;
    return plan;
}

void SyncManagerUnit::complete(std::size_t n, bool ecat_write) {
    State& state = states_[n];
    state.open = false;
    if (channels_[n].mailbox()) state.full = ecat_write;
    if (ecat_write) {
        state.write_event = true;
        state.read_event = false;
        state.last_buffer = static_cast<std::uint8_t>(state.last_buffer >= 2 ? 0 : state.last_buffer + 1);
        events_.written = static_cast<std::uint8_t>(events_.written | bit(n));
    } else {
        state.read_event = true;
        state.write_event = false;
        events_.read = static_cast<std::uint8_t>(events_.read | bit(n));
    }
    write_status(n);
}

void SyncManagerUnit::pdi_mailbox_consumed(int n) {
    const auto i = static_cast<std::size_t>(n);
    states_[i].full = false;
    states_[i].open = false;
    states_[i].write_event = false;
    states_[i].read_event = true;
    write_status(i);
}

void SyncManagerUnit::pdi_mailbox_filled(int n) {
    const auto i = static_cast<std::size_t>(n);
    states_[i].full = true;
    states_[i].open = false;
    states_[i].write_event = true;
    states_[i].read_event = false;
    write_status(i);
}

void SyncManagerUnit::set_pdi_deactivated(int n, bool deactivated) {
    const auto i = static_cast<std::size_t>(n);
    const std::uint16_t address = sm_register(i, kPdiControlOffset);
    const auto value = memory_.u8(address);
    memory_.set_u8(address, static_cast<std::uint8_t>(deactivated ? (value | 0x01) : (value & ~0x01)));
    if (channels_[i].pdi_deactivated == deactivated) return;
    channels_[i].pdi_deactivated = deactivated;
    // Deactivation resets the buffer: it has to be written first afterwards.
    reset_channel(i);
}

bool SyncManagerUnit::repeat_requested(int n) const {
    const auto i = static_cast<std::size_t>(n);
    return ((memory_.u8(sm_register(i, kActivateOffset)) ^ memory_.u8(sm_register(i, kPdiControlOffset))) &
            kRepeatBit) != 0;
}

void SyncManagerUnit::acknowledge_repeat(int n) {
    const auto i = static_cast<std::size_t>(n);
    const std::uint16_t address = sm_register(i, kPdiControlOffset);
    const auto request = static_cast<std::uint8_t>(memory_.u8(sm_register(i, kActivateOffset)) & kRepeatBit);
    memory_.set_u8(address, static_cast<std::uint8_t>((memory_.u8(address) & ~kRepeatBit) | request));
}

void SyncManagerUnit::note_register_write(std::uint32_t address, std::size_t length) {
    if (active_mask_ == 0 || length == 0) return;
    const auto end = static_cast<std::uint32_t>(address + length);
    for (std::size_t n = 0; n < channels_.size(); ++n) {
        const SmChannel& ch = channels_[n];
        if ((active_mask_ & bit(n)) == 0 || ch.pdi_deactivated || !ch.ecat_writes() || !ch.watchdog_trigger()) continue;
        if (ch.start < end && address < ch.end()) watchdog_triggered_ = true;
    }
}

bool SyncManagerUnit::take_watchdog_trigger() {
    const bool triggered = watchdog_triggered_;
    watchdog_triggered_ = false;
    return triggered;
}

SyncManagerUnit::Events SyncManagerUnit::take_events() {
    const Events taken = events_;
    events_ = {};
    return taken;
}

void SyncManagerUnit::reset_channel(std::size_t n) {
    states_[n] = State{};
    write_status(n);
}

void SyncManagerUnit::write_status(std::size_t n) {
    const SmChannel& ch = channels_[n];
    const State& state = states_[n];
    std::uint8_t status = 0;
    if (ch.active()) {
        status = static_cast<std::uint8_t>((state.write_event ? 0x01 : 0x00) | (state.read_event ? 0x02 : 0x00));
        status = static_cast<std::uint8_t>(status | (ch.mailbox() ? (state.full ? 0x08 : 0x00) : (state.last_buffer << 4)));
    }
    memory_.set_u8(sm_register(n, kStatusOffset), status);
    // The SyncManager bits of the ECAT event request (0x0210 b4-b11).
    const bool event = (ch.control & kEcatIrqEnable) != 0 && (status & 0x03) != 0;
    auto request = memory_.load<std::uint16_t>(reg::kEcatEventRequest);
    const auto mask = static_cast<std::uint16_t>(1U << (regs::kEventFirstSmBit + n));
    request = static_cast<std::uint16_t>(event ? (request | mask) : (request & ~mask));
    memory_.store<std::uint16_t>(reg::kEcatEventRequest, request);
}

}  // namespace ecpair::sim
