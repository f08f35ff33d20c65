#include "ecpair/eni/hot_connect_groups.hpp"

#include <algorithm>
#include <numeric>

#include "ecpair/eni/eni_topology.hpp"

namespace ecpair::eni {
namespace {

std::vector<std::size_t> ring_order_of(const std::vector<Slave>& slaves) {
    std::vector<std::size_t> order(slaves.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&slaves](std::size_t a, std::size_t b) {
        return slaves[a].info.ring_position < slaves[b].info.ring_position;
    });
    return order;
}

}  // namespace

std::vector<std::size_t> group_members(const std::vector<Slave>& slaves, std::size_t head) {
    const auto order = ring_order_of(slaves);
    const auto at = std::find(order.begin(), order.end(), head);
    const std::size_t count = slaves[head].hot_connect ? std::max<std::uint32_t>(1, slaves[head].hot_connect->group_member_count) : 1;
    const auto available = static_cast<std::size_t>(order.end() - at);
    return {at, at + static_cast<std::ptrdiff_t>(std::min(count, available))};
}

HotConnectGroups HotConnectGroups::of(const EniConfig& eni) {
    HotConnectGroups result;
    result.group_of_.assign(eni.slaves.size(), 0);
    result.groups_.push_back(HotConnectGroup{0, "mandatory", std::nullopt, {}, false, {}});
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        const auto& slave = eni.slaves[i];
        if (!slave.hot_connect) continue;
        HotConnectGroup group;
        group.number = result.groups_.size();
        group.name = slave.hot_connect->group_name.empty() ? slave.info.name : slave.hot_connect->group_name;
        group.head = i;
        group.members = group_members(eni.slaves, i);
        group.floating = is_floating_head(eni, i);
        group.identification = identification_of(slave);
        for (const auto member : group.members) {
            if (result.group_of_[member] == 0) result.group_of_[member] = group.number;
        }
        result.groups_.push_back(std::move(group));
    }
    for (const auto index : ring_order_of(eni.slaves)) {
        if (result.group_of_[index] == 0) result.groups_[0].members.push_back(index);
    }
    return result;
}

bool HotConnectGroups::is_head(std::size_t slave) const {
    const auto& g = groups_[group_of_[slave]];
    return g.head && *g.head == slave;
}

}  // namespace ecpair::eni
