#pragma once
// The SII EEPROM behind its ESC interface (0x0500-0x050F; datasheet I §11.2,
// esc-facts.md §2):
//
//  - 0x0500 b0 offers the EEPROM to the PDI, b1 forces it back to ECAT. While
//    the PDI side controls it (0x0500 b0 or 0x0501 b0), ECAT writes to
//    0x0502-0x050F are ignored;
//  - 0x0502 control/status: the command (b10:8) runs when the frame that wrote
//    it ends: 001 read (8 bytes into 0x0508, this ESC reads 8-byte chunks and
//    says so in b6), 010 write (the word in 0x0508 at the word address in
//    0x0504; needs write enable b0 in the same frame, else b14), 100 reload
//    (re-reads the configuration area; b11 checksum error, b12 not loaded).
//    Any other command, or an address past the EEPROM, sets b13. Writing
//    command 000 clears b13/b14. The command bits and write enable clear
//    themselves and busy (b15) is never seen set: the emulated EEPROM answers
//    at once;
//  - the configuration area (words 0-6) is loaded into 0x0140-0x0145,
//    0x0150-0x0153 and 0x0982 when the checksum is right; the station alias
//    (word 4 -> 0x0012) only at the first load after power-on, as on real
//    ESCs (datasheet I §11.1). The image itself survives power cycles.

#include <cstdint>
#include <vector>

#include "esc_memory.hpp"

namespace ecpair::sim {

class SiiEeprom {
public:
    explicit SiiEeprom(std::vector<std::uint8_t> image);

    const std::vector<std::uint8_t>& image() const { return image_; }
    // Rewrites word 4 and the checksum (the new alias shows after power-on).
    void set_alias(std::uint16_t alias);
    std::uint16_t alias() const;  // word 4 as the EEPROM holds it now

    // Power-on: interface registers to their reset state, then the first load
    // of the configuration area. Returns whether it loaded (checksum right).
    bool power_on(EscMemory& memory);

    // Before the frame's register writes are committed: drops ECAT writes to
    // the interface while the PDI side controls the EEPROM.
    void filter_staged(EscMemory& memory) const;
    // After they were committed: runs a command the master issued. Returns
    // whether the configuration area is loaded afterwards (a reload may fail).
    bool on_ecat_write(EscMemory& memory);

    bool loaded() const { return loaded_; }

private:
    bool load_configuration(EscMemory& memory, bool first_load);
    void read_chunk(EscMemory& memory, std::uint32_t word_address, std::uint16_t& status) const;
    void write_word(EscMemory& memory, std::uint32_t word_address, std::uint16_t& status);

    std::vector<std::uint8_t> image_;
    bool loaded_ = false;
};

}  // namespace ecpair::sim
