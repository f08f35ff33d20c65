#pragma once
// Compares what a scan found with what the ENI configures, the way
// commercial masters report a bus mismatch: for each configured slave
// whether it is present, where it hangs (the previous slave's station
// address and port), the configured and the found identity, and the
// identification value (station alias or explicit device ID) expected and
// read.
//
// Presence: every configured slave is mandatory unless it belongs to a
// Hot-Connect group (Slave/HotConnect: the head and its GroupMemberCnt-1
// followers in ring order). A group is present when the slave found where
// its head belongs matches the head; then its members are compared one by
// one like mandatory slaves. An absent group takes no ring position, so the
// slaves behind it are expected that many positions earlier. The walk that
// decides this is topology_match.hpp; this is its result in one list.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::bus {

enum class SlaveMatch : std::uint8_t {
    Match,                // vendor, product, revision (serial, identification when configured) agree
    WrongIdentity,        // a different device sits at this position
    WrongIdentification,  // the right device, but its alias / explicit device ID differs from the ENI
    Missing,              // a mandatory slave is configured but nothing answers at its position
    Absent,               // an optional (Hot-Connect) slave is not there: not a mismatch
    Unexpected,           // answers but is not configured
    Unreadable,           // answers but its SII could not be read
};

std::string_view to_string(SlaveMatch match);

// Station alias register and explicit device ID register (Identification/Ado).
inline constexpr std::uint16_t kIdentificationAlias = 0x0012;
inline constexpr std::uint16_t kIdentificationExplicitId = 0x0134;

struct IdentificationCheck {
    std::uint16_t ado = 0;
    std::uint16_t expected = 0;
    std::optional<std::uint16_t> read;  // nullopt: could not be read
    friend bool operator==(const IdentificationCheck&, const IdentificationCheck&) = default;
};

struct SlaveComparison {
    std::uint16_t position = 0;  // ring position where the slave was found or expected (0-based)
    SlaveMatch match = SlaveMatch::Match;
    const eni::Slave* configured = nullptr;        // points into the EniConfig
    std::optional<std::size_t> configured_index;   // index into EniConfig::slaves
    const ScannedSlave* found = nullptr;           // points into the ScanReport
    bool optional = false;                         // member of a Hot-Connect group
    std::optional<IdentificationCheck> identification;  // when the ENI asks for one
    // Where it hangs: found slaves as the bus shows it, missing ones as the
    // ENI configures it (PreviousPort, or the previous slave).
    std::optional<std::uint16_t> previous_station;
    std::optional<char> previous_port;
    std::optional<std::uint16_t> previous_position;  // the bus position of the previous slave, when found
    std::string note;  // why an unexpected slave is unexpected ("duplicate of ...", "belongs ...")

    // Whether this entry keeps the bus from matching the ENI.
    bool is_mismatch() const { return match != SlaveMatch::Match && match != SlaveMatch::Absent; }
    std::string describe() const;  // the mismatch descriptor: one line for logs and operators
};

// Identification values that a plain scan does not read: the explicit device
// ID (0x0134) needs an AL control request. Indexed by scan position; a
// position without a value (or beyond the vector) counts as unreadable.
struct IdentificationReadings {
    std::vector<std::optional<std::uint16_t>> explicit_device_ids;
};

// One entry per configured slave (ring order), then one per unexpected slave
// found behind them. Pointers in the result refer into `report` and `eni`:
// keep both alive. Identification Value 0 (or none) means "not checked", as a
// serial number of 0 does.
std::vector<SlaveComparison> compare_with_eni(const ScanReport& report, const eni::EniConfig& eni,
                                              const IdentificationReadings& readings = {});
// True when no entry is a mismatch (absent Hot-Connect groups are fine).
bool all_match(const std::vector<SlaveComparison>& comparisons);

}  // namespace ecpair::bus
