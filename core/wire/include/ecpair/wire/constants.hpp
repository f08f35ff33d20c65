#pragma once
// Sizes and numbers of the EtherCAT frame format (esc-facts.md §1).

#include <cstddef>
#include <cstdint>

namespace ecpair::wire {

inline constexpr std::uint16_t kEtherTypeEtherCat = 0x88A4;
inline constexpr std::uint16_t kEtherTypeVlan = 0x8100;

inline constexpr std::size_t kEthernetHeaderSize = 14;
inline constexpr std::size_t kVlanTagSize = 4;
inline constexpr std::size_t kEcatHeaderSize = 2;
inline constexpr std::size_t kDatagramHeaderSize = 10;
inline constexpr std::size_t kWkcSize = 2;
inline constexpr std::size_t kDatagramOverhead = kDatagramHeaderSize + kWkcSize;

// Ethernet frame sizes without the 4-byte FCS (the kernel never shows it).
inline constexpr std::size_t kMinFrameSize = 60;
inline constexpr std::size_t kMaxFrameSize = 1514;
inline constexpr std::size_t kMaxFrameSizeVlan = 1518;

// The EtherCAT payload of one untagged frame: 1500 - 2 header bytes.
inline constexpr std::size_t kMaxEcatPayload = 1498;
inline constexpr std::size_t kMaxDatagramData = kMaxEcatPayload - kDatagramOverhead;  // 1486

// EtherCAT header "Type" for datagrams; ESCs process only this type.
inline constexpr std::uint8_t kEcatTypeDatagrams = 1;

// Datagram length word: [10:0] length, [13:11] reserved, [14] circulating, [15] more.
inline constexpr std::uint16_t kLengthMask = 0x07FF;
inline constexpr std::uint16_t kReservedMask = 0x3800;
inline constexpr std::uint16_t kCirculatingBit = 0x4000;
inline constexpr std::uint16_t kMoreBit = 0x8000;

}  // namespace ecpair::wire
