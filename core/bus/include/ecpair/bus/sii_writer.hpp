#pragma once
// Writes words of a slave's SII EEPROM through the ESC's EEPROM interface
// (esc-facts.md §2): the data word into 0x0508, then the write command
// (bits 10:8 = 010) with write enable (bit 0) and the word address in one
// 6-byte write at 0x0502, then poll busy; an error bit names the failure.
//
// set_station_alias() programs the configured station alias (word 4) and
// rewrites the checksum of the configuration area (word 7: CRC-8,
// x^8+x^2+x+1, initial 0xFF, over words 0-6), without which the slave could
// not load its configuration and leave INIT (hot-connect.md §9). The ESC
// takes the alias into 0x0012 at its next power-on.

#include <cstdint>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/bus/sii_reader.hpp"

namespace ecpair::bus {

// The SII configuration area's checksum over words 0-6.
std::uint8_t sii_configuration_crc(const std::vector<std::uint16_t>& words_0_to_6);

class SiiWriter {
public:
    explicit SiiWriter(BusAccess& bus, std::uint32_t busy_polls = 100) : bus_(bus), busy_polls_(busy_polls) {}

    Expected<void, BusError> write_word(SlaveAddress slave, std::uint16_t word_address, std::uint16_t value);
    // Word 4 and the checksum in word 7; returns the alias that was there before.
    Expected<std::uint16_t, BusError> set_station_alias(SlaveAddress slave, std::uint16_t alias);

private:
    BusAccess& bus_;
    std::uint32_t busy_polls_;
};

}  // namespace ecpair::bus
