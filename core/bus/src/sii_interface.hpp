#pragma once
// The ESC's EEPROM interface as the master sees it (SII control/status
// register 0x0502, esc-facts.md §2): the bits SiiReader and SiiWriter both
// test, the wait for a command to finish and the error they both report.

#include <cstdint>
#include <string>

#include "ecpair/bus/bus_access.hpp"

namespace ecpair::bus::sii_interface {

inline constexpr std::uint16_t kBusy = 0x8000;
inline constexpr std::uint16_t kWriteEnableError = 0x4000;
inline constexpr std::uint16_t kCommandError = 0x2000;
inline constexpr std::uint16_t kEightByteRead = 0x0040;
// The command in control bits 10:8, as the high byte of the control word.
inline constexpr std::uint8_t kReadCommand = 0x01;
inline constexpr std::uint8_t kWriteCommand = 0x02;
inline constexpr std::uint8_t kWriteEnable = 0x01;  // low byte, bit 0

BusError error(SlaveAddress slave, const std::string& what);

// Polls the control/status word until the busy bit clears (at most `polls`
// reads) and returns it; an error when the slave does not answer or stays busy.
Expected<std::uint16_t, BusError> wait_idle(BusAccess& bus, SlaveAddress slave, std::uint32_t polls);

// Writes command 000 when an earlier command left an error bit set in `status`.
Expected<void, BusError> clear_errors(BusAccess& bus, SlaveAddress slave, std::uint16_t status);

}  // namespace ecpair::bus::sii_interface
