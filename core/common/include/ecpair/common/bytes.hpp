#pragma once
// Little-endian load/store on byte spans. EtherCAT is little-endian on the
// wire; these are the only place where byte order is spelled out. Callers
// check bounds before calling (the codec validates lengths once per frame).

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

namespace ecpair {

using Bytes = std::span<std::uint8_t>;
using ConstBytes = std::span<const std::uint8_t>;

template <class T>
    requires std::is_unsigned_v<T>
constexpr T load_le(ConstBytes bytes, std::size_t offset = 0) {
    assert(offset + sizeof(T) <= bytes.size());
    T value = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        value = static_cast<T>(value | (static_cast<T>(bytes[offset + i]) << (8 * i)));
    }
    return value;
}

template <class T>
    requires std::is_unsigned_v<T>
constexpr void store_le(Bytes bytes, std::size_t offset, T value) {
    assert(offset + sizeof(T) <= bytes.size());
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        bytes[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
    }
}

constexpr std::uint16_t load_be16(ConstBytes bytes, std::size_t offset) {
    assert(offset + 2 <= bytes.size());
    return static_cast<std::uint16_t>((bytes[offset] << 8) | bytes[offset + 1]);
}

constexpr void store_be16(Bytes bytes, std::size_t offset, std::uint16_t value) {
    assert(offset + 2 <= bytes.size());
    bytes[offset] = static_cast<std::uint8_t>(value >> 8);
    bytes[offset + 1] = static_cast<std::uint8_t>(value);
}

}  // namespace ecpair
