#pragma once
// How a configured slave is identified beyond its vendor, product and
// revision (hot-connect.md §9), read from Slave/Info/Identification:
//
//   Ado 0x0012            station alias (loaded from SII word 4 at power-on)
//   Ado 0x0134            explicit device ID (ETG.1020: ID request in AL
//                         control bit 5, the ID in the AL status code register)
//   Ado in process RAM    input word: the value sits in the slave's input
//   (0x1000 and above)    process data at that ESC address (readable once the
//                         slave's input SyncManager runs, i.e. from SAFEOP)
//   any other Ado         a 16-bit register read at that address
//
// No Identification, EnableIdentification="False", or Value 0 mean None:
// the station address from the ENI only.

#include <cstdint>
#include <string_view>

#include "ecpair/eni/model.hpp"

namespace ecpair::eni {

enum class IdentificationMode : std::uint8_t { None, StationAlias, ExplicitDeviceId, InputWord, Register };
std::string_view to_string(IdentificationMode mode);

inline constexpr std::uint16_t kStationAliasRegister = 0x0012;
inline constexpr std::uint16_t kExplicitDeviceIdRegister = 0x0134;
inline constexpr std::uint16_t kProcessRamStart = 0x1000;

struct IdentificationSpec {
    IdentificationMode mode = IdentificationMode::None;
    std::uint16_t ado = 0;
    std::uint16_t value = 0;  // the expected value (not 0 unless mode is None)
    friend bool operator==(const IdentificationSpec&, const IdentificationSpec&) = default;
};

IdentificationSpec identification_of(const Slave& slave);

}  // namespace ecpair::eni
