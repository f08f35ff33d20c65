#pragma once
// Which configured slave sits at which bus position: the identification of
// the bus against the ENI at start-up and after every topology change
// (hot-connect.md §1, §3, §8, §9).
//
// The match walks the bus depth first, in the order frames visit it (DL
// status tells which ports lead on, dl_ports.hpp), next to the ENI's tree
// (eni_topology.hpp). At each port it expects the slave the ENI configures
// there:
//   - found and matching (vendor, product, revision, serial when the ENI
//     gives one, the identification value, a group head's IdentifyCmds):
//     it is that slave;
//   - a mandatory slave or a member of a present group that does not match
//     is a mismatch at its place (WrongIdentity, WrongIdentification,
//     Unreadable) -- unless the bus slave is an unknown slave spliced in
//     front of it (then the next one matches), or a floating group;
//   - an optional group head that does not match: the group is absent there
//     and the bus slave is unexpected -- or it is a floating group, which
//     may be plugged in anywhere;
//   - a port where the ENI configures nothing: a floating group head, or an
//     unexpected slave (with everything behind it);
//   - nothing there: the configured slave is missing (mandatory) or absent
//     (optional), or, when positions are left over at the end, found behind
//     a line break (the slaves after a break form a fragment of their own).
// Duplicates: the first slave found that matches takes the place; a second
// one with the same identity and identification is unexpected ("duplicate").
// A known slave plugged at the wrong port is unexpected too ("belongs ...").
//
// Without DL status (a scan that could not read it, or a made-up report) a
// slave's ports are unknown: then the next position is taken as the next
// slave the ENI configures, and an optional group only where its head
// matches (the ring order of the ENI, as compare_with_eni always did).
//
// Identification values other than the station alias (read by the scan)
// come from an IdentificationProbe, asked only where a candidate needs them.
// Input words are not checked here: they are readable only in SAFEOP, and
// the bring-up of the slave checks them (see hot_connect_bring_up).

#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::bus {

class IdentificationProbe {
public:
    virtual ~IdentificationProbe() = default;
    // The value at `spec.ado` of the slave at `position` (explicit device ID
    // or a register); nullopt when it cannot be read.
    virtual std::optional<std::uint16_t> read(std::uint16_t position, const eni::IdentificationSpec& spec) = 0;
    // Whether the IdentifyCmds of the group headed by ENI slave `head` pass
    // at `position`. True when the head has none.
    virtual bool identify_cmds_pass(std::uint16_t position, std::size_t head) = 0;
};

// Answers from readings taken beforehand (explicit device IDs by position);
// IdentifyCmds always pass.
class ReadingsProbe final : public IdentificationProbe {
public:
    explicit ReadingsProbe(const IdentificationReadings& readings) : readings_(readings) {}
    std::optional<std::uint16_t> read(std::uint16_t position, const eni::IdentificationSpec& spec) override;
    bool identify_cmds_pass(std::uint16_t, std::size_t) override { return true; }

private:
    const IdentificationReadings& readings_;
};

enum class GroupState : std::uint8_t {
    Present,  // every member found as configured
    Absent,   // no member found (an optional group that is not plugged in)
    Refused,  // found, but something does not match: not used until it does
};
std::string_view to_string(GroupState state);

struct TopologyMatch {
    TopologyMatch() = default;
    // `comparisons` points into the report and ENI, not into this object: copies are fine.

    std::vector<SlaveComparison> comparisons;              // configured slaves in ring order, then unexpected ones
    std::vector<std::optional<std::uint16_t>> position;    // per ENI slave: where it was found as configured
    std::vector<GroupState> groups;                        // per group number (0 = mandatory)
    std::vector<std::size_t> group_of;                     // per ENI slave: its group number
    std::uint16_t slaves_on_bus = 0;                       // positions that answered

    // Per ENI slave: found as configured (and for an optional slave, its whole group).
    std::vector<bool> present() const;
    // Mismatches that keep a bus from starting: a mandatory slave that is not
    // as configured, or an unexpected slave. A refused optional group does not.
    bool blocking() const;
};

// `report` and `eni` must outlive the result (its comparisons point into them).
TopologyMatch match_topology(const ScanReport& report, const eni::EniConfig& eni,
                             const eni::HotConnectGroups& groups, IdentificationProbe& probe);

}  // namespace ecpair::bus
