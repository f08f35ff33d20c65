#pragma once
// Compares what a scan found with what the ENI configures, position by
// position, the way commercial masters report a bus mismatch: for each
// position the configured and the found identity, and where the slave hangs
// (the previous slave's station address and port from the ENI).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::bus {

enum class SlaveMatch : std::uint8_t {
    Match,          // vendor, product, revision (and serial when configured) agree
    WrongIdentity,  // a different device sits at this position
    Missing,        // configured but nothing answers at this position
    Unexpected,     // answers but is not configured
    Unreadable,     // answers but its SII could not be read
};

std::string_view to_string(SlaveMatch match);

struct SlaveComparison {
    std::uint16_t position = 0;
    SlaveMatch match = SlaveMatch::Match;
    const eni::Slave* configured = nullptr;  // points into the EniConfig
    const ScannedSlave* found = nullptr;     // points into the ScanReport
    std::optional<std::uint16_t> previous_station;  // from the ENI's PreviousPort (or the previous slave)
    std::optional<char> previous_port;
    std::string describe() const;  // one line for logs and operators
};

// Pointers in the result refer into `report` and `eni`: keep both alive.
std::vector<SlaveComparison> compare_with_eni(const ScanReport& report, const eni::EniConfig& eni);
bool all_match(const std::vector<SlaveComparison>& comparisons);

}  // namespace ecpair::bus
