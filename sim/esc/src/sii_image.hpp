#pragma once
// The SII EEPROM contents of an emulated slave, generated from its
// description (ETG.1000.6 §5.4 / ETG.2010, esc-facts.md §2 "SII words"):
//
//   words 0x00-0x07  ESC configuration area A: PDI control/ESC config (0x0C05:
//                    SPI PDI, DC sync and latch units, no device emulation;
//                    a digital I/O terminal without microcontroller: 0x0104,
//                    digital I/O PDI with device emulation),
//                    SYNC pulse length, the station alias in word 4 and the
//                    CRC-8 (x^8+x^2+x+1, initial 0xFF) of words 0-6 in word 7
//   words 0x08-0x0F  vendor ID, product code, revision, serial number
//   words 0x14-0x1B  bootstrap and standard mailbox offsets/sizes (0 if none)
//   word  0x1C       mailbox protocols
//   words 0x3E/0x3F  EEPROM size (KiBit - 1) and version (1)
//   from  0x40       categories: strings (10: 1 = name, 2 = group "ecsim",
//                    3 = order "VVVVVVVV:PPPPPPPP"), general (30), FMMU usage
//                    (40), SyncManagers (41), TxPDOs (50), RxPDOs (51), then
//                    the end marker 0xFFFF.
//
// The image has the full size of the EEPROM it claims to be; words past the
// content read 0xFFFF like erased cells.

#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/sim/esc.hpp"
#include "esc_layout.hpp"

namespace ecpair::sim {

namespace sii {
inline constexpr std::uint16_t kConfigWords = 7;  // words covered by the checksum
inline constexpr std::uint16_t kPdiControlWord = 0x0C05;
inline constexpr std::uint16_t kDigitalIoDeviceEmulation = 0x0104;
inline constexpr std::uint16_t kSyncPulseLength = 1000;  // 10 us in 10 ns units
}  // namespace sii

std::vector<std::uint8_t> build_sii_image(const EscDescription& description, const EscLayout& layout);

// CRC-8 of the configuration area (poly 0x07, init 0xFF, no reflection).
std::uint8_t sii_crc8(ConstBytes bytes);
// Whether word 7 holds the checksum of words 0-6.
bool sii_checksum_valid(ConstBytes image);
// Sets word 4 (the alias) and recomputes the checksum.
void sii_set_alias(Bytes image, std::uint16_t alias);

}  // namespace ecpair::sim
