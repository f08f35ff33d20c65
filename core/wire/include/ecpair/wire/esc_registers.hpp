#pragma once
// Names for the ESC registers a master and the simulator touch
// (esc-facts.md §2; Beckhoff ESC datasheet section II). Addresses only:
// the meaning of the bits is with the code that uses them.

#include <cstdint>

namespace ecpair::wire::reg {

inline constexpr std::uint16_t kType = 0x0000;
inline constexpr std::uint16_t kRevision = 0x0001;
inline constexpr std::uint16_t kBuild = 0x0002;
inline constexpr std::uint16_t kFmmuCount = 0x0004;
inline constexpr std::uint16_t kSmCount = 0x0005;
inline constexpr std::uint16_t kRamSize = 0x0006;
inline constexpr std::uint16_t kPortDescriptor = 0x0007;
inline constexpr std::uint16_t kFeatures = 0x0008;
inline constexpr std::uint16_t kStationAddress = 0x0010;
inline constexpr std::uint16_t kStationAlias = 0x0012;
inline constexpr std::uint16_t kDlControl = 0x0100;
inline constexpr std::uint16_t kDlControlLoop = 0x0101;
inline constexpr std::uint16_t kDlStatus = 0x0110;
inline constexpr std::uint16_t kAlControl = 0x0120;
inline constexpr std::uint16_t kAlStatus = 0x0130;
inline constexpr std::uint16_t kAlStatusCode = 0x0134;
inline constexpr std::uint16_t kPdiControl = 0x0140;
inline constexpr std::uint16_t kEcatEventMask = 0x0200;
inline constexpr std::uint16_t kEcatEventRequest = 0x0210;
inline constexpr std::uint16_t kRxErrorCounters = 0x0300;
inline constexpr std::uint16_t kLostLinkCounters = 0x0310;
inline constexpr std::uint16_t kWatchdogDivider = 0x0400;
inline constexpr std::uint16_t kSiiConfig = 0x0500;
inline constexpr std::uint16_t kSiiPdiAccess = 0x0501;
inline constexpr std::uint16_t kSiiControl = 0x0502;
inline constexpr std::uint16_t kSiiAddress = 0x0504;
inline constexpr std::uint16_t kSiiData = 0x0508;
inline constexpr std::uint16_t kFmmuBase = 0x0600;
inline constexpr std::uint16_t kFmmuSize = 16;
inline constexpr std::uint16_t kSmBase = 0x0800;
inline constexpr std::uint16_t kSmSize = 8;
inline constexpr std::uint16_t kDcReceiveTimes = 0x0900;
inline constexpr std::uint16_t kDcSystemTime = 0x0910;
inline constexpr std::uint16_t kDcReceiveTimeEcu = 0x0918;
inline constexpr std::uint16_t kDcSystemTimeOffset = 0x0920;
inline constexpr std::uint16_t kDcSystemTimeDelay = 0x0928;
inline constexpr std::uint16_t kDcSystemTimeDifference = 0x092C;
inline constexpr std::uint16_t kDcSpeedCounterStart = 0x0930;
inline constexpr std::uint16_t kDcCycleUnitControl = 0x0980;
inline constexpr std::uint16_t kDcActivation = 0x0981;
inline constexpr std::uint16_t kDcStartTime = 0x0990;
inline constexpr std::uint16_t kDcCycleTime0 = 0x09A0;
inline constexpr std::uint16_t kDcCycleTime1 = 0x09A4;

// The NOP datagram address of Cyclic Master Red Frames (design.md §3).
inline constexpr std::uint16_t kMasterRedAdo = 0x4155;

// SII word addresses (esc-facts.md §2, SII words).
namespace sii {
inline constexpr std::uint16_t kAlias = 0x0004;
inline constexpr std::uint16_t kChecksum = 0x0007;
inline constexpr std::uint16_t kVendorId = 0x0008;
inline constexpr std::uint16_t kProductCode = 0x000A;
inline constexpr std::uint16_t kRevision = 0x000C;
inline constexpr std::uint16_t kSerial = 0x000E;
inline constexpr std::uint16_t kBootstrapRxMailbox = 0x0014;
inline constexpr std::uint16_t kStandardRxMailbox = 0x0018;
inline constexpr std::uint16_t kMailboxProtocols = 0x001C;
inline constexpr std::uint16_t kSize = 0x003E;
inline constexpr std::uint16_t kVersion = 0x003F;
inline constexpr std::uint16_t kFirstCategory = 0x0040;

inline constexpr std::uint16_t kCategoryStrings = 10;
inline constexpr std::uint16_t kCategoryGeneral = 30;
inline constexpr std::uint16_t kCategoryFmmu = 40;
inline constexpr std::uint16_t kCategorySyncManager = 41;
inline constexpr std::uint16_t kCategoryTxPdo = 50;
inline constexpr std::uint16_t kCategoryRxPdo = 51;
inline constexpr std::uint16_t kCategoryDc = 60;
inline constexpr std::uint16_t kCategoryEnd = 0xFFFF;
}  // namespace sii

}  // namespace ecpair::wire::reg
