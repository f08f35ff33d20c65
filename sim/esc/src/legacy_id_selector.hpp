#pragma once
// ETG.1020 legacy handling of an ID selector (a rotary switch) that races the
// SII alias (hot-connect.md §10). The slave's host reads the selector once,
// right after power-on:
//   selector 0                 nothing: 0x0012 is what the SII says;
//   selector != 0, SII alias 0 0x0012 = selector;
//   both != 0                  0x0012 = selector, and the race procedure:
//                              the SII alias is overwritten with 0 when the
//                              slave enters PREOP from INIT; a SAFEOP request
//                              is refused (PREOP + error, AL status code 0x0061
//                              "device identification value updated").
// The error clears on an INIT request once it has been shown, on a power
// cycle (the SII alias is 0 by then), or on a successful SDO write to the
// reload object (kReloadObject). An INIT request before the error was shown
// does not clear it: every master starts with one, and the procedure exists
// so that the master notices the new value.

#include <cstdint>
#include <memory>
#include <string>

#include <spdlog/logger.h>

#include "al_state_machine.hpp"
#include "esc_memory.hpp"
#include "sii_eeprom.hpp"

namespace ecpair::sim {

inline constexpr std::uint16_t kDeviceIdUpdated = 0x0061;
// Manufacturer-specific object a master writes (any value) to accept the new
// identification value without going through INIT. Our choice of index.
inline constexpr std::uint16_t kReloadObject = 0x2F00;

class LegacyIdSelector {
public:
    LegacyIdSelector(std::shared_ptr<spdlog::logger> log, std::string owner)
        : log_(std::move(log)), owner_(std::move(owner)) {}

    // The switch position read at the next power-on.
    void set(std::uint16_t selector) { selector_ = selector; }
    std::uint16_t selector() const { return selector_; }

    // After the SII load of a power-on (0x0012 holds the SII alias).
    void on_power_on(EscMemory& memory, const SiiEeprom& eeprom);
    // After the master's AL control request was handled.
    void after_request(AlControlWord request, AlState before, AlState after, std::uint16_t status_code,
                       SiiEeprom& eeprom);
    // The AL status code that refuses entering `target` (0: allowed).
    std::uint16_t refusal(AlState target) const;
    // The master wrote the reload object.
    void reload_written();

    bool race() const { return race_; }

private:
    void clear(std::string_view why);

    std::shared_ptr<spdlog::logger> log_;
    std::string owner_;
    std::uint16_t selector_ = 0;
    bool race_ = false;           // the error flag of the race procedure
    bool shown_ = false;          // a SAFEOP request was refused with 0x0061
    bool clear_sii_pending_ = false;
};

}  // namespace ecpair::sim
