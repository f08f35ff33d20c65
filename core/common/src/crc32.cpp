// CRC-32 (IEEE), byte-wise with a 256-entry table built at compile time:
// each table entry is the CRC contribution of one byte value, so the loop
// does one lookup and one shift per input byte.

#include "ecpair/common/crc32.hpp"

#include <array>

namespace ecpair {
namespace {

constexpr std::uint32_t kReflectedPolynomial = 0xEDB88320u;

constexpr std::array<std::uint32_t, 256> make_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t value = 0; value < table.size(); ++value) {
        std::uint32_t crc = value;
        for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ kReflectedPolynomial : crc >> 1;
        table[value] = crc;
    }
    return table;
}

constexpr std::array<std::uint32_t, 256> kTable = make_table();

}  // namespace

std::uint32_t crc32(ConstBytes data, std::uint32_t previous) {
    std::uint32_t crc = ~previous;
    for (const std::uint8_t byte : data) crc = kTable[(crc ^ byte) & 0xFFu] ^ (crc >> 8);
    return ~crc;
}

}  // namespace ecpair
