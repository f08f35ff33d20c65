#include "ecpair/hotconnect/hot_connect_view.hpp"

#include <algorithm>

namespace ecpair::hotconnect {

std::string_view to_string(GroupStatus status) {
    switch (status) {
        case GroupStatus::Present: return "present";
        case GroupStatus::Absent: return "absent";
        case GroupStatus::Refused: return "refused";
        case GroupStatus::Joining: return "joining";
        case GroupStatus::AwaitingAccept: return "awaiting accept";
    }
    return "?";
}

std::vector<GroupView> group_views(const eni::EniConfig& eni, const eni::HotConnectGroups& groups,
                                   const std::vector<master::SlaveStateEntry>& image) {
    std::vector<GroupView> views;
    for (const auto& group : groups.groups()) {
        if (!group.optional() && group.members.empty()) continue;
        GroupView view;
        view.number = group.number;
        view.name = group.name;
        view.floating = group.floating;
        view.identification = group.identification;
        bool any = false;
        bool all_present = true;
        std::uint8_t flags = 0;
        for (const auto index : group.members) {
            const auto& entry = index < image.size() ? image[index] : master::SlaveStateEntry{};
            view.members.push_back(
                MemberView{index, eni.slaves[index].info.name, eni.slaves[index].info.phys_addr, entry.present, entry.al_status});
            any = any || entry.present || (entry.hot_connect & (master::kJoining | master::kAwaitingAccept | master::kRefused));
            all_present = all_present && entry.present && (entry.hot_connect & master::kGroupPresent);
            flags = static_cast<std::uint8_t>(flags | entry.hot_connect);
        }
        if ((flags & master::kRefused) != 0) {
            view.status = GroupStatus::Refused;
        } else if ((flags & master::kAwaitingAccept) != 0) {
            view.status = GroupStatus::AwaitingAccept;
        } else if ((flags & master::kJoining) != 0) {
            view.status = GroupStatus::Joining;
        } else if (all_present && !group.members.empty()) {
            view.status = GroupStatus::Present;
        } else if (!group.optional()) {
            // The mandatory group before Hot-Connect knew anything: what the slave monitor says.
            const bool monitor_all = std::all_of(view.members.begin(), view.members.end(),
                                                 [](const MemberView& m) { return m.present; });
            view.status = monitor_all ? GroupStatus::Present : GroupStatus::Refused;
        } else {
            view.status = any ? GroupStatus::Refused : GroupStatus::Absent;
        }
        views.push_back(std::move(view));
    }
    return views;
}

std::uint32_t presence_mask(const std::vector<GroupView>& groups) {
    std::uint32_t mask = 0;
    for (const auto& g : groups) {
        if (g.number >= 1 && g.number <= 32 && g.status == GroupStatus::Present) mask |= 1u << (g.number - 1);
    }
    return mask;
}

MismatchView mismatch_view(const bus::SlaveComparison& c) {
    MismatchView v;
    v.position = c.position;
    v.match = c.match;
    v.configured = c.configured_index;
    v.previous_station = c.previous_station;
    v.previous_port = c.previous_port;
    v.previous_position = c.previous_position;
    if (c.found) {
        v.found = c.found->identity;
        v.found_station = c.found->station_address;
    }
    v.identification = c.identification;
    v.text = c.describe();
    return v;
}

}  // namespace ecpair::hotconnect
