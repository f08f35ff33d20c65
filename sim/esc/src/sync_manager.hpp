#pragma once
// The eight SyncManagers of an ESC (datasheet I §8, esc-facts.md §2).
//
// The configuration lives in the registers at 0x0800 + 8n; refresh() decodes
// it after the master wrote there and resets a channel whose configuration
// changed. For every ECAT access to RAM, plan_ecat_access() decides byte
// ranges the SyncManagers refuse and updates the buffer state:
//
//  - buffered (3-buffer) mode behaves as plain RAM for the master; completing
//    an access (reaching the last byte) only updates the status register;
//  - mailbox mode alternates: the writer may write only while the buffer is
//    empty, the reader may read only while it is full; an access has to start
//    at the first byte of the buffer, and reaching the last byte flips the
//    state (full <-> empty). Refused bytes do not count for the WKC;
//  - a channel with length 0 or 1, or disabled by the master (0x0806 b0 = 0),
//    does not interfere; one deactivated by the PDI (0x0807 b0 = 1) refuses
//    every byte of its buffer;
//  - an ECAT write into the buffer of an active channel whose control byte
//    has the watchdog trigger (b6) is noted for the process data watchdog
//    (take_watchdog_trigger()), one-byte buffers included.
//
// The status register (0x0805 + 8n: b0 write event, b1 read event, b3
// mailbox full, b5:4 last buffer) and the SyncManager bits of the ECAT event
// request (0x0210 b4-b11) are kept up to date in memory. The PDI side (the
// mailbox service, the slave stack) fills, drains and deactivates channels
// through the pdi_* calls.

#include <array>
#include <cstddef>
#include <cstdint>

#include "esc_memory.hpp"

namespace ecpair::sim {

struct SmChannel {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    bool enabled = false;          // 0x0806 b0, set by the master
    bool pdi_deactivated = false;  // 0x0807 b0, set by the slave stack

    bool mailbox() const { return (control & 0x03) == 0x02; }
    bool ecat_writes() const { return (control & 0x0C) == 0x04; }
    bool watchdog_trigger() const { return (control & 0x40) != 0; }
    // Whether the channel manages its buffer at all.
    bool active() const { return enabled && length > 0; }
    std::uint32_t end() const { return std::uint32_t{start} + length; }
};

// Byte ranges of one ECAT access the SyncManagers refuse.
struct SmAccessPlan {
    struct Range {
        std::uint32_t begin = 0;
        std::uint32_t end = 0;
    };
    std::array<Range, 8> refused{};  // sorted by begin, may overlap
    std::size_t refused_count = 0;
    bool any_permitted = false;
};

class SyncManagerUnit {
public:
    static constexpr int kCount = regs::kSmCount;

    explicit SyncManagerUnit(EscMemory& memory);

    // Power-on: every channel unconfigured and empty.
    void reset();
    // Re-reads the configuration registers. Returns a bit per channel whose
    // activation register (0x0806 + 8n) changed.
    std::uint8_t refresh();

    // Decides an ECAT access to [address, address + length) and applies its
    // effect on the buffer states.
    SmAccessPlan plan_ecat_access(std::uint32_t address, std::size_t length, bool ecat_write);

    const SmChannel& channel(int n) const { return channels_[static_cast<std::size_t>(n)]; }
    bool mailbox_full(int n) const { return states_[static_cast<std::size_t>(n)].full; }

    // ---- PDI side
    void pdi_mailbox_consumed(int n);  // the stack read an ECAT-written mailbox: empty again
    void pdi_mailbox_filled(int n);    // the stack wrote an ECAT-read mailbox: full
    void set_pdi_deactivated(int n, bool deactivated);
    // Mailbox repeat (datasheet I §8.6): the master toggled the repeat request
    // (0x0806 b1) and the stack has not yet copied it to 0x0807 b1.
    bool repeat_requested(int n) const;
    void acknowledge_repeat(int n);

    // Channels whose buffer the master completed writing / reading since the
    // last call (a bit per channel), for the PDI side to react to.
    struct Events {
        std::uint8_t written = 0;
        std::uint8_t read = 0;
    };
    Events take_events();
    // An ECAT write to registers (staged until the end of the frame): a
    // SyncManager over the digital outputs (0x0F00-0x0F03) with the watchdog
    // trigger is fed by it like one over RAM.
    void note_register_write(std::uint32_t address, std::size_t length);
    // Whether a watched buffer was written since the last call.
    bool take_watchdog_trigger();

private:
    struct State {
        bool full = false;        // mailbox: a buffer is waiting for its reader
        bool open = false;        // the current access began at the first byte
        std::uint8_t last_buffer = 3;  // buffered mode: 3 = nothing written yet
        bool write_event = false;
        bool read_event = false;
    };

    void reset_channel(std::size_t n);
    void complete(std::size_t n, bool ecat_write);
    void write_status(std::size_t n);

    EscMemory& memory_;
    std::array<SmChannel, kCount> channels_{};
    std::array<State, kCount> states_{};
    std::array<std::uint8_t, kCount> activation_{};
    std::uint8_t active_mask_ = 0;
    Events events_{};
    bool watchdog_triggered_ = false;
};

}  // namespace ecpair::sim
