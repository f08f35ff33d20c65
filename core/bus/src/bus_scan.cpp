#include "ecpair/bus/bus_scan.hpp"

#include "ecpair/bus/sii_reader.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::bus {
namespace {

// Reads what the registers tell about one slave; SII last because it is slow.
ScannedSlave scan_slave(BusAccess& bus, std::uint16_t position) {
    ScannedSlave slave;
    slave.position = position;
    const auto address = SlaveAddress::position(position);

    auto note = [&slave](const std::string& what) {
        if (!slave.error.empty()) slave.error += "; ";
        slave.error += what;
    };

    if (auto r = read_register(bus, address, wire::reg::kStationAddress, 4); r && r->wkc == 1) {
        slave.station_address = load_le<std::uint16_t>(r->data, 0);
        slave.alias = load_le<std::uint16_t>(r->data, 2);
    } else {
        note("station address not readable");
    }
    if (auto r = read_register(bus, address, wire::reg::kDlStatus, 2); r && r->wkc == 1) {
        slave.dl_status = load_le<std::uint16_t>(r->data, 0);
        slave.dl_status_read = true;
    } else {
        note("DL status not readable");
    }
    if (auto r = read_register(bus, address, wire::reg::kAlStatus, 6); r && r->wkc == 1) {
        slave.al_status.raw = r->data[0];
        slave.al_status_code = load_le<std::uint16_t>(r->data, 4);
    } else {
        note("AL status not readable");
    }

    SiiReader sii(bus);
    auto words = sii.read_words(address, wire::reg::sii::kVendorId, 8);
    if (words) {
        const auto dword = [&words](std::size_t i) {
            return static_cast<std::uint32_t>((*words)[i]) | (static_cast<std::uint32_t>((*words)[i + 1]) << 16);
        };
        slave.identity = SlaveIdentity{dword(0), dword(2), dword(4), dword(6)};
    } else {
        note(words.error().message);
    }
    return slave;
}

}  // namespace

Expected<ScanReport, BusError> scan_bus(BusAccess& bus) {
    DatagramRequest count;
    count.command = wire::Command::Brd;
    count.address = wire::DatagramHeader::physical(0, wire::reg::kType);
    count.data.assign(2, 0);
    auto counted = bus.exchange(count);
    if (!counted) return unexpected(counted.error());

    ScanReport report;
    report.responding = counted->wkc;
    logger("bus")->info("scan: {} slave(s) answer", report.responding);
    for (std::uint16_t position = 0; position < report.responding; ++position) {
        report.slaves.push_back(scan_slave(bus, position));
    }
    return report;
}

}  // namespace ecpair::bus
