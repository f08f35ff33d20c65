#include "coe_data_types.hpp"

#include <algorithm>
#include <array>

#include "ecpair/wire/sdo_information.hpp"

namespace ecpair::sim {

std::uint16_t coe_data_type(std::string_view eni_name) {
    struct Entry {
        std::string_view name;
        std::uint16_t code;
    };
    static constexpr std::array kTypes = {
        Entry{"BOOL", 0x01},  Entry{"BIT", 0x01},    Entry{"SINT", 0x02},   Entry{"INT", 0x03},
        Entry{"DINT", 0x04},  Entry{"USINT", 0x05},  Entry{"UINT", 0x06},   Entry{"UDINT", 0x07},
        Entry{"REAL", 0x08},  Entry{"STRING", 0x09}, Entry{"INT24", 0x10},  Entry{"LREAL", 0x11},
        Entry{"LINT", 0x15},  Entry{"UINT24", 0x16}, Entry{"ULINT", 0x1B},  Entry{"BYTE", 0x1E},
        Entry{"WORD", 0x1F},  Entry{"DWORD", 0x20},  Entry{"BIT1", 0x30},   Entry{"BIT2", 0x31},
        Entry{"BIT3", 0x32},  Entry{"BIT4", 0x33},   Entry{"BIT5", 0x34},   Entry{"BIT6", 0x35},
        Entry{"BIT7", 0x36},  Entry{"BIT8", 0x37},   Entry{"BITARR8", 0x2D}, Entry{"BITARR16", 0x2E},
        Entry{"BITARR32", 0x2F},
    };
    const auto it = std::find_if(kTypes.begin(), kTypes.end(), [&](const Entry& e) { return e.name == eni_name; });
    return it == kTypes.end() ? std::uint16_t{0} : it->code;
}

std::uint16_t coe_data_type_of_size(std::size_t bytes) {
    switch (bytes) {
        case 1: return wire::coe_type::kUnsigned8;
        case 2: return wire::coe_type::kUnsigned16;
        case 4: return wire::coe_type::kUnsigned32;
        case 8: return wire::coe_type::kUnsigned64;
        default: return wire::coe_type::kOctetString;
    }
}

}  // namespace ecpair::sim
