#pragma once
// CoE data type indices (ETG.1000.6 table 64) for the ENI's <DataType>
// names, shared by the SII PDO entries and the object dictionary's entry
// descriptions.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ecpair::sim {

// 0 when the name is not a base type the simulator knows.
std::uint16_t coe_data_type(std::string_view eni_name);
// The type an entry of `bytes` bytes of unknown meaning is described with:
// UNSIGNED8/16/32/64, else OCTET_STRING.
std::uint16_t coe_data_type_of_size(std::size_t bytes);

}  // namespace ecpair::sim
