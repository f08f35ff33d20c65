// The rules of Hot-Connect groups (hot-connect.md §1) that a file must keep:
//   - a group has as many slaves behind its head in ring order as
//     GroupMemberCnt says;
//   - no group inside a group;
//   - every member but the head hangs on a slave of its own group;
//   - no mandatory slave hangs on a slave of an optional group (it would
//     vanish with the group).

#include <fmt/format.h>

#include "ecpair/eni/eni_topology.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

std::string label(const Slave& slave) {
    return fmt::format("'{}' (PhysAddr {})", slave.info.name, slave.info.phys_addr);
}

const Element& placement_element(const Element& slave, std::optional<Element>& storage) {
    const auto previous = slave.children("PreviousPort");
    if (previous.empty()) return slave;
    storage = previous.front();
    return *storage;
}

}  // namespace

void check_hot_connect_groups(const std::vector<Slave>& slaves, const std::vector<Element>& elements) {
    std::vector<std::size_t> group_of(slaves.size(), 0);  // 0: mandatory; else the head's index + 1
    for (std::size_t head = 0; head < slaves.size(); ++head) {
        const auto& hot_connect = slaves[head].hot_connect;
        if (!hot_connect) continue;
        const auto members = group_members(slaves, head);
        const auto hc_element = elements[head].required_child("HotConnect");
        if (members.size() < hot_connect->group_member_count) {
            hc_element.required_child("GroupMemberCnt")
                .fail(fmt::format("GroupMemberCnt is {}, but only {} slave(s) from {} on are left in ring order",
                                  hot_connect->group_member_count, members.size(), label(slaves[head])));
        }
        for (const auto member : members) {
            if (member != head && slaves[member].hot_connect) {
                elements[member].required_child("HotConnect").fail(
                    fmt::format("{} heads a Hot-Connect group but is itself a member of the group of {}",
                                label(slaves[member]), label(slaves[head])));
            }
            group_of[member] = head + 1;
        }
    }

    const auto topology = EniTopology::of(slaves);
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        const auto& attachment = topology.attachment(i);
        if (!attachment) continue;
        const bool head = slaves[i].hot_connect.has_value();
        const auto parent_group = group_of[attachment->parent];
        std::optional<Element> storage;
        const auto& where = placement_element(elements[i], storage);
        if (group_of[i] == 0 && parent_group != 0) {
            where.fail(fmt::format("mandatory slave {} hangs on {}, a member of the optional Hot-Connect group of {}",
                                   label(slaves[i]), label(slaves[attachment->parent]),
                                   label(slaves[parent_group - 1])));
        }
        if (group_of[i] != 0 && !head && parent_group != group_of[i]) {
            where.fail(fmt::format("{} is a member of the Hot-Connect group of {} but hangs on {}, outside that group",
                                   label(slaves[i]), label(slaves[group_of[i] - 1]),
                                   label(slaves[attachment->parent])));
        }
    }
}

}  // namespace ecpair::eni::detail
