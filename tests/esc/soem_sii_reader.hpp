#pragma once
// Reads a slave's SII through its EEPROM interface the way SOEM does
// (ethercatmain.c: ecx_readeepromFP writes control + address with one 6-byte
// FPWR at 0x0502, polls the busy bit, then reads 0x0508; ecx_siigetbyte
// caches the 4- or 8-byte chunks) and parses it like ecx_siifind,
// ecx_siistring, ecx_siiSM and ecx_siiPDO. Written independently of the
// simulator's SII generator so that it checks it.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "esc_test_support.hpp"

namespace ecpair::sim::test {

class SoemSiiReader {
public:
    SoemSiiReader(Line& line, std::uint16_t station) : line_(line), station_(station) {}

    std::uint8_t byte(std::uint32_t address);
    std::uint16_t word(std::uint32_t word_address);
    std::uint32_t dword(std::uint32_t word_address);

    // Byte address of the category's length word, 0 when absent (ecx_siifind).
    std::uint32_t find(std::uint16_t category);
    // String `index` (1-based) of the strings category (ecx_siistring).
    std::string string(std::uint8_t index);

    struct SyncManager {
        std::uint16_t start = 0;
        std::uint16_t length = 0;
        std::uint8_t control = 0;
        std::uint8_t enable = 0;
        std::uint8_t type = 0;
    };
    std::vector<SyncManager> sync_managers();
    // Bits of the PDOs per SyncManager, TxPDOs (inputs) or RxPDOs (outputs) (ecx_siiPDO).
    std::array<std::uint32_t, 8> pdo_bits(bool tx);

    bool eight_byte_reads() const { return eight_bytes_; }
    int read_commands() const { return read_commands_; }

private:
    void read_chunk(std::uint32_t word_address);

    Line& line_;
    std::uint16_t station_;
    std::map<std::uint32_t, std::uint8_t> cache_;
    bool eight_bytes_ = false;
    int read_commands_ = 0;
};

// CRC-8 of the ESC configuration area as IgH's ec_slave_sii_crc computes it
// (augmented form, initial value 0x48), independent of the simulator's.
std::uint8_t igh_sii_crc(const std::vector<std::uint8_t>& data);

}  // namespace ecpair::sim::test
