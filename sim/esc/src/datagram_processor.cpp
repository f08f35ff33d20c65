// One switch over the command decides the addressing; the memory side is
// physical_access() for ADO-addressed commands and logical_access() for the
// FMMU-addressed ones. Both return the WKC increment.

#include "datagram_processor.hpp"

#include <algorithm>

#include "dl_registers.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

std::uint32_t with_adp(std::uint32_t address, std::uint16_t adp) {
    return (address & 0xFFFF0000U) | adp;
}

// Whether the datagram's data covers register `address`.
bool covers(const wire::DatagramView& datagram, std::uint16_t address) {
    const std::uint32_t ado = datagram.address() >> 16;
    return ado <= address && address < ado + datagram.data().size();
}

}  // namespace

DatagramProcessor::DatagramProcessor(EscMemory& memory, PhysicalAccess& physical, FmmuUnit& fmmus)
    : memory_(memory), physical_(physical), fmmus_(fmmus) {}

bool DatagramProcessor::process(const wire::DatagramView& datagram) {
    using wire::Command;
    const std::uint32_t address = datagram.address();
    const auto adp = static_cast<std::uint16_t>(address & 0xFFFF);
    const auto incremented = static_cast<std::uint16_t>(adp + 1);
    std::uint16_t wkc_increment = 0;
    bool addressed = true;
    switch (datagram.command()) {
        case Command::Aprd:
        case Command::Apwr:
        case Command::Aprw:
        case Command::Armw: {
            static constexpr std::array kAccess = {Access::Read, Access::Write, Access::ReadWrite};
            const Command command = datagram.command();
            const Access access = command == Command::Armw
                                      ? Access::ReadOrWrite
                                      : kAccess[static_cast<std::size_t>(command) - static_cast<std::size_t>(Command::Aprd)];
            addressed = command == Command::Armw || adp == 0;
            wkc_increment = physical_access(datagram, access, adp == 0);
            if (command == Command::Armw && adp == 0 && wkc_increment != 0 && covers(datagram, reg::kDcSystemTime)) {
                dc_access_.reference_read = true;
            }
            datagram.set_address(with_adp(address, incremented));
            break;
        }
        case Command::Fprd:
        case Command::Fpwr:
        case Command::Fprw: {
            static constexpr std::array kAccess = {Access::Read, Access::Write, Access::ReadWrite};
            const auto command = static_cast<std::size_t>(datagram.command());
            const Access access = kAccess[command - static_cast<std::size_t>(Command::Fprd)];
            addressed = configured_address_matches(adp);
            wkc_increment = physical_access(datagram, access, addressed);
            if (datagram.command() == Command::Fpwr && addressed && wkc_increment != 0 &&
                covers(datagram, reg::kDcReceiveTimes)) {
                dc_access_.port_latch = true;
            }
            break;
        }
        case Command::Frmw: {
            const bool reference = configured_address_matches(adp);
            wkc_increment = physical_access(datagram, Access::ReadOrWrite, reference);
            if (reference && wkc_increment != 0 && covers(datagram, reg::kDcSystemTime)) dc_access_.reference_read = true;
            break;
        }
        case Command::Brd:
            wkc_increment = physical_access(datagram, Access::BroadcastRead, true);
            datagram.set_address(with_adp(address, incremented));
            break;
        case Command::Bwr:
            wkc_increment = physical_access(datagram, Access::Write, true);
            if (wkc_increment != 0 && covers(datagram, reg::kDcReceiveTimes)) dc_access_.port_latch = true;
            datagram.set_address(with_adp(address, incremented));
            break;
        case Command::Brw:
            wkc_increment = physical_access(datagram, Access::BroadcastReadWrite, true);
            datagram.set_address(with_adp(address, incremented));
            break;
        case Command::Lrd:
        case Command::Lwr:
        case Command::Lrw:
            addressed = fmmus_.maps(address, datagram.data().size());
            if (addressed) wkc_increment = logical_access(datagram);
            break;
        case Command::Nop:
        default: addressed = false; break;  // NOP and reserved commands touch nothing
    }
    if (wkc_increment != 0) datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + wkc_increment));
    const auto irq = static_cast<std::uint16_t>(memory_.load<std::uint16_t>(reg::kEcatEventRequest) &
                                                memory_.load<std::uint16_t>(reg::kEcatEventMask));
    if (irq != 0) datagram.set_irq(static_cast<std::uint16_t>(datagram.irq() | irq));
    return addressed;
}

bool DatagramProcessor::configured_address_matches(std::uint16_t adp) const {
    if (adp == memory_.load<std::uint16_t>(reg::kStationAddress)) return true;
    const bool alias_enabled = DlControl::decode(memory_.load<std::uint32_t>(reg::kDlControl)).alias_enabled;
    return alias_enabled && adp == memory_.load<std::uint16_t>(reg::kStationAlias);
}

std::uint16_t DatagramProcessor::physical_access(const wire::DatagramView& datagram, Access access, bool addressed) {
    const Bytes data = datagram.data();
    const auto ado = static_cast<std::uint16_t>(datagram.address() >> 16);
    switch (access) {
        case Access::Read: return addressed && physical_.read(ado, data, ReadMode::Copy) ? 1 : 0;
        case Access::BroadcastRead: return physical_.read(ado, data, ReadMode::Or) ? 1 : 0;
        case Access::Write: return addressed && physical_.write(ado, data) ? 1 : 0;
        case Access::ReadOrWrite:
            return (addressed ? physical_.read(ado, data, ReadMode::Copy) : physical_.write(ado, data)) ? 1 : 0;
        case Access::ReadWrite:
        case Access::BroadcastReadWrite: {
            if (!addressed) return 0;
            std::copy(data.begin(), data.end(), arrived_.begin());
            const ReadMode mode = access == Access::ReadWrite ? ReadMode::Copy : ReadMode::Or;
            const bool read = physical_.read(ado, data, mode);
            const auto write_address = static_cast<std::uint16_t>(ado + memory_.load<std::uint16_t>(regs::kRwOffset));
            const bool written = physical_.write(write_address, ConstBytes(arrived_.data(), data.size()));
            return static_cast<std::uint16_t>((read ? 1 : 0) + (written ? 2 : 0));
        }
    }
    return 0;
}

std::uint16_t DatagramProcessor::logical_access(const wire::DatagramView& datagram) {
    const Bytes data = datagram.data();
    const std::uint32_t address = datagram.address();
    switch (datagram.command()) {
        case wire::Command::Lrd: return fmmus_.read(address, data, physical_) ? 1 : 0;
        case wire::Command::Lwr: return fmmus_.write(address, data, physical_) ? 1 : 0;
        default: break;
    }
    // LRW: read first, then write the data as it arrived. Only the part the
    // write FMMUs cover needs keeping.
    const auto window = fmmus_.write_window(address, data.size());
    const auto kept = data.subspan(window.begin, window.end - window.begin);
    std::copy(kept.begin(), kept.end(), arrived_.begin());
    const bool read = fmmus_.read(address, data, physical_);
    const bool written =
        window.begin < window.end &&
        fmmus_.write(static_cast<std::uint32_t>(address + window.begin),
                     ConstBytes(arrived_.data(), kept.size()), physical_);
    return static_cast<std::uint16_t>((read ? 1 : 0) + (written ? 2 : 0));
}

}  // namespace ecpair::sim
