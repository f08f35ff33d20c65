#pragma once
// The Hot-Connect groups of an ENI (hot-connect.md §1, §2). A slave with a
// <HotConnect> element heads a group of GroupMemberCnt slaves: itself and
// the slaves that follow it in ring order. Every slave outside a group is
// in group 0, the mandatory group. Group numbers 1..n follow the file order
// of their heads. A group is floating when its head is a floating head
// (eni_topology.hpp): it may be plugged in at any port; otherwise it is
// pinned to the port its head's PreviousPort names.
//
// The loader checks the rules (members exist and hang behind their head, no
// group inside a group, no mandatory slave behind an optional one), so a
// loaded EniConfig always gives a consistent HotConnectGroups.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/eni/identification.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::eni {

struct HotConnectGroup {
    std::size_t number = 0;            // 0: the mandatory group
    std::string name;                  // GroupName, or the head's name when the ENI gives none
    std::optional<std::size_t> head;   // EniConfig::slaves index; none for group 0
    std::vector<std::size_t> members;  // ring order, the head first
    bool floating = false;
    IdentificationSpec identification;  // the head's

    bool optional() const { return number != 0; }
};

class HotConnectGroups {
public:
    static HotConnectGroups of(const EniConfig& eni);

    // [0] is the mandatory group (possibly empty), then one per <HotConnect>.
    const std::vector<HotConnectGroup>& groups() const { return groups_; }
    std::size_t optional_count() const { return groups_.size() - 1; }
    std::size_t group_of(std::size_t slave) const { return group_of_[slave]; }
    bool is_optional(std::size_t slave) const { return group_of_[slave] != 0; }
    bool is_head(std::size_t slave) const;
    const HotConnectGroup& group(std::size_t number) const { return groups_[number]; }

private:
    std::vector<HotConnectGroup> groups_;
    std::vector<std::size_t> group_of_;  // per EniConfig::slaves index
};

// The members of the group headed by `head`: the head and the next
// GroupMemberCnt-1 slaves in ring order (as many as there are).
std::vector<std::size_t> group_members(const std::vector<Slave>& slaves, std::size_t head);

}  // namespace ecpair::eni
