#pragma once
// Reads a slave's SII EEPROM through the ESC's EEPROM interface
// (0x0500-0x050F, esc-facts.md §2): take the EEPROM for ECAT, wait until the
// interface is idle, write the read command and word address in one 6-byte
// write at 0x0502, poll busy, then read 4 or 8 bytes at 0x0508 (the ESC says
// which in 0x0502 bit 6).

#include <cstdint>
#include <vector>

#include "ecpair/bus/bus_access.hpp"

namespace ecpair::bus {

class SiiReader {
public:
    explicit SiiReader(BusAccess& bus, std::uint32_t busy_polls = 100) : bus_(bus), busy_polls_(busy_polls) {}

    // `word_count` 16-bit words starting at `word_address`.
    Expected<std::vector<std::uint16_t>, BusError> read_words(SlaveAddress slave, std::uint16_t word_address,
                                                              std::size_t word_count);
    Expected<std::uint32_t, BusError> read_dword(SlaveAddress slave, std::uint16_t word_address);

private:
    Expected<std::vector<std::uint8_t>, BusError> read_chunk(SlaveAddress slave, std::uint16_t word_address);

    BusAccess& bus_;
    std::uint32_t busy_polls_;
};

}  // namespace ecpair::bus
