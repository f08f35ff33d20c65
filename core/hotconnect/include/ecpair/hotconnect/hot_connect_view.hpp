#pragma once
// What an operator is shown of Hot-Connect: each group with its members and
// whether it is present, and the mismatch descriptors of the last scan
// (hot-connect.md §5, §6). group_views() reads only the ENI and the slave
// state image, so an INACTIVE master, whose image is mirrored from the
// ACTIVE's (with the Hot-Connect flags), answers like the ACTIVE.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/bus/topology_match.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/master/slave_state_image.hpp"

namespace ecpair::hotconnect {

enum class GroupStatus : std::uint8_t { Present, Absent, Refused, Joining, AwaitingAccept };
std::string_view to_string(GroupStatus status);

struct MemberView {
    std::size_t slave = 0;  // ENI index
    std::string name;
    std::uint16_t station = 0;
    bool present = false;
    std::uint8_t al_status = 0;  // as last read (0: not read)
};

struct GroupView {
    std::size_t number = 0;  // 0: mandatory
    std::string name;
    bool floating = false;
    eni::IdentificationSpec identification;
    GroupStatus status = GroupStatus::Absent;
    std::vector<MemberView> members;
};

std::vector<GroupView> group_views(const eni::EniConfig& eni, const eni::HotConnectGroups& groups,
                                   const std::vector<master::SlaveStateEntry>& image);
// Bit g-1 set: optional group g (1..32) is present.
std::uint32_t presence_mask(const std::vector<GroupView>& groups);

// A mismatch descriptor, copied out of a match (hot-connect.md §6).
struct MismatchView {
    std::uint16_t position = 0;
    bus::SlaveMatch match = bus::SlaveMatch::Match;
    std::optional<std::size_t> configured;  // ENI index (a wrong or missing slave)
    std::optional<std::uint16_t> previous_station;
    std::optional<char> previous_port;
    std::optional<std::uint16_t> previous_position;
    std::optional<bus::SlaveIdentity> found;
    std::uint16_t found_station = 0;
    std::optional<bus::IdentificationCheck> identification;
    std::string text;  // the descriptor in one line
};

MismatchView mismatch_view(const bus::SlaveComparison& comparison);

}  // namespace ecpair::hotconnect
