#pragma once
// The scan before INIT -> PREOP: count the slaves (BRD), read each
// position's identity from the SII (bus::scan_bus), and match the bus
// against the ENI (bus::match_topology), reading identification values where
// a candidate needs them (BusIdentificationProbe). The outcome says which
// configured slaves are present, how far each one's position moved (absent
// optional slaves ahead of it, a floating group plugged elsewhere), and
// whether the bus matches.
//
// Explicit device ID (Identification Ado 0x0134): write AL control with the
// slave's current state plus bit 5 (ID request), wait until AL status shows
// bit 5 (ID loaded), read 0x0134, then write the plain state back.

#include <chrono>
#include <cstdint>
#include <optional>
#include <stop_token>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/bus/topology_match.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::sequencer {

struct ScanOutcome {
    ScanOutcome() = default;
    // `comparisons` points into `report`: moving keeps the vectors' elements in place, copying would not.
    ScanOutcome(const ScanOutcome&) = delete;
    ScanOutcome& operator=(const ScanOutcome&) = delete;
    ScanOutcome(ScanOutcome&&) = default;
    ScanOutcome& operator=(ScanOutcome&&) = default;

    bus::ScanReport report;
    bus::IdentificationReadings readings;
    std::vector<bus::SlaveComparison> comparisons;
    std::vector<bool> present;                  // per EniConfig::slaves entry
    std::vector<std::uint16_t> position_shift;  // per EniConfig::slaves entry: configured minus found position
    std::vector<bus::GroupState> groups;        // per Hot-Connect group number (0 = mandatory)
    bool matches = false;                       // no mandatory slave missing or wrong, nothing unexpected
                                                // (a refused optional group is left out, not a reason to stop)

    std::vector<const bus::SlaveComparison*> mismatches() const;
};

// Reads the explicit device ID of the slave at `position` (see above);
// nullopt when it does not answer the request in time.
std::optional<std::uint16_t> read_explicit_device_id(bus::BusAccess& bus, Clock& clock, std::uint16_t position,
                                                     std::chrono::milliseconds timeout, std::stop_token stop = {});

class StartupScan {
public:
    StartupScan(bus::BusAccess& bus, Clock& clock) : bus_(bus), clock_(clock) {}

    Expected<ScanOutcome, bus::BusError> run(const eni::EniConfig& eni, std::stop_token stop = {});

private:
    bus::BusAccess& bus_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
