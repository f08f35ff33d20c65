#include "hot_connect_scan.hpp"

#include "ecpair/bus/sii_reader.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/eni/identification.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::hotconnect {
namespace {

constexpr std::uint16_t kStatusBlock = wire::reg::kDlStatus;                 // 0x0110
constexpr std::size_t kStatusBlockLength = wire::reg::kAlStatusCode + 2 - kStatusBlock;  // up to 0x0135

}  // namespace

Expected<HotConnectScan, bus::BusError> scan_for_hot_connect(bus::BusAccess& bus, const eni::EniConfig& eni,
                                                             const std::vector<bool>& present) {
    bus::DatagramRequest count;
    count.command = wire::Command::Brd;
    count.address = wire::DatagramHeader::physical(0, wire::reg::kType);
    count.data.assign(2, 0);
    auto counted = bus.exchange(count);
    if (!counted) return unexpected(counted.error());

    std::map<std::uint16_t, std::size_t> by_station;
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        if (i < present.size() && present[i]) by_station.emplace(eni.slaves[i].info.phys_addr, i);
    }

    HotConnectScan scan;
    scan.report.responding = counted->wkc;
    for (std::uint16_t position = 0; position < counted->wkc; ++position) {
        bus::ScannedSlave slave;
        slave.position = position;
        const auto address = bus::SlaveAddress::position(position);
        if (auto r = bus::read_register(bus, address, wire::reg::kStationAddress, 4); r && r->wkc == 1) {
            slave.station_address = load_le<std::uint16_t>(r->data, 0);
            slave.alias = load_le<std::uint16_t>(r->data, 2);
        } else if (!r) {
            return unexpected(r.error());
        } else {
            slave.error = "station address not readable";
        }
        if (auto r = bus::read_register(bus, address, kStatusBlock, kStatusBlockLength); r && r->wkc == 1) {
            slave.dl_status = load_le<std::uint16_t>(r->data, 0);
            slave.dl_status_read = true;
            slave.al_status.raw = r->data[wire::reg::kAlStatus - kStatusBlock];
            slave.al_status_code = load_le<std::uint16_t>(r->data, wire::reg::kAlStatusCode - kStatusBlock);
        } else if (!r) {
            return unexpected(r.error());
        }
        if (const auto known = by_station.find(slave.station_address); known != by_station.end()) {
            const auto& info = eni.slaves[known->second].info;
            slave.identity = bus::SlaveIdentity{info.vendor_id, info.product_code, info.revision_no, info.serial_no.value_or(0)};
            scan.known.emplace(position, known->second);
        } else {
            bus::SiiReader sii(bus);
            if (auto words = sii.read_words(address, wire::reg::sii::kVendorId, 8)) {
                const auto dword = [&words](std::size_t i) {
                    return static_cast<std::uint32_t>((*words)[i]) | (static_cast<std::uint32_t>((*words)[i + 1]) << 16);
                };
                slave.identity = bus::SlaveIdentity{dword(0), dword(2), dword(4), dword(6)};
            } else {
                slave.error = words.error().message;
            }
        }
        scan.report.slaves.push_back(std::move(slave));
    }
    return scan;
}

std::optional<std::uint16_t> HotConnectProbe::read(std::uint16_t position, const eni::IdentificationSpec& spec) {
    if (const auto known = scan_.known.find(position); known != scan_.known.end()) {
        const auto expected = eni::identification_of(eni_.slaves[known->second]);
        if (expected.ado == spec.ado) return expected.value;
    }
    return bus_probe_.read(position, spec);
}

bool HotConnectProbe::identify_cmds_pass(std::uint16_t position, std::size_t head) {
    if (const auto known = scan_.known.find(position); known != scan_.known.end()) return known->second == head;
    return bus_probe_.identify_cmds_pass(position, head);
}

}  // namespace ecpair::hotconnect
