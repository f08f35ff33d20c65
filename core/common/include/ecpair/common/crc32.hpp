#pragma once
// CRC-32 as Ethernet, zlib and PNG compute it (IEEE 802.3: polynomial
// 0x04C11DB7 reflected, initial value and final XOR 0xFFFFFFFF).
// crc32("123456789") == 0xCBF43926.

#include <cstdint>

#include "ecpair/common/bytes.hpp"

namespace ecpair {

// The CRC of `data`. To checksum pieces one after the other, pass the CRC
// of what came before: crc32(b, crc32(a)) == crc32(a followed by b).
std::uint32_t crc32(ConstBytes data, std::uint32_t previous = 0);

}  // namespace ecpair
