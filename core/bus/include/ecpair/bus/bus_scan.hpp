#pragma once
// A read-only scan of the bus: how many slaves answer, and for each ring
// position its station address, alias, AL state and status code, DL status
// and its identity from the SII. Nothing is written except the EEPROM
// interface registers needed to read the SII.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/wire/al_status.hpp"

namespace ecpair::bus {

struct SlaveIdentity {
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code = 0;
    std::uint32_t revision_no = 0;
    std::uint32_t serial_no = 0;
    friend bool operator==(const SlaveIdentity&, const SlaveIdentity&) = default;
};

struct ScannedSlave {
    std::uint16_t position = 0;
    std::uint16_t station_address = 0;
    std::uint16_t alias = 0;
    wire::AlStatus al_status;
    std::uint16_t al_status_code = 0;
    std::uint16_t dl_status = 0;
    bool dl_status_read = false;            // false: dl_status says nothing (the ports are unknown)
    std::optional<SlaveIdentity> identity;  // nullopt when the SII could not be read
    std::string error;                      // why something could not be read
};

struct ScanReport {
    std::uint16_t responding = 0;  // WKC of a BRD: the number of slaves on the bus
    std::vector<ScannedSlave> slaves;
};

Expected<ScanReport, BusError> scan_bus(BusAccess& bus);

}  // namespace ecpair::bus
