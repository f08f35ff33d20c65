#pragma once
// AL status (0x0130) and AL status code (0x0134) in words.

#include <cstdint>
#include <string>
#include <string_view>

namespace ecpair::wire {

struct AlStatus {
    static constexpr std::uint8_t kStateMask = 0x0F;
    static constexpr std::uint8_t kErrorBit = 0x10;
    static constexpr std::uint8_t kIdLoadedBit = 0x20;

    std::uint8_t raw = 0;

    std::uint8_t state() const { return raw & kStateMask; }
    bool error() const { return (raw & kErrorBit) != 0; }
    bool id_loaded() const { return (raw & kIdLoadedBit) != 0; }
    // "OP", "SAFEOP+ERR", "0x0b" for an undefined state value.
    std::string to_string() const;
};

// "INIT", "PREOP", "BOOT", "SAFEOP", "OP", or the hex value.
std::string al_state_name(std::uint8_t state);

// The text for an AL status code ("invalid requested state change"), or
// "unknown AL status code" for codes not in the table.
std::string_view al_status_code_text(std::uint16_t code);

}  // namespace ecpair::wire
