// The walk of match_topology (see the header). State: the next bus position
// to hand out, per ENI slave its comparison (decided once), the unexpected
// slaves found, and the configured slaves whose port showed nothing (they
// may still turn up behind a line break).

#include "ecpair/bus/topology_match.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "ecpair/bus/dl_ports.hpp"
#include "ecpair/eni/eni_topology.hpp"

namespace ecpair::bus {
namespace {

bool identity_matches(const eni::SlaveInfo& configured, const SlaveIdentity& found) {
    if (configured.vendor_id != found.vendor_id || configured.product_code != found.product_code ||
        configured.revision_no != found.revision_no) {
        return false;
    }
    // A serial of 0 in the ENI means "any device of this type".
    return !configured.serial_no || *configured.serial_no == 0 || *configured.serial_no == found.serial_no;
}

struct Verdict {
    SlaveMatch match = SlaveMatch::Match;
    std::optional<IdentificationCheck> identification;
};

class Walk {
public:
    Walk(const ScanReport& report, const eni::EniConfig& eni, const eni::HotConnectGroups& groups,
         IdentificationProbe& probe)
        : report_(report),
          eni_(eni),
          groups_(groups),
          probe_(probe),
          topology_(eni::EniTopology::of(eni)),
          decided_(eni.slaves.size()) {
        result_.position.assign(eni.slaves.size(), std::nullopt);
        result_.slaves_on_bus = static_cast<std::uint16_t>(report.slaves.size());
    }

    TopologyMatch run() {
        if (!eni_.slaves.empty()) {
            if (report_.slaves.empty()) {
                unresolved_.push_back(0);
            } else {
                const std::uint16_t q = next_++;
                found_at(0, std::nullopt, 0, q);
            }
        }
        // Floating heads that are never reached from a configured port are decided at the end.
        resolve_leftovers();
        for (const auto slave : unresolved_) mark_not_found(slave);
        for (std::size_t i = 0; i < eni_.slaves.size(); ++i) {
            if (!decided_[i]) mark_not_found(i);
        }
        return finish();
    }

private:
    std::optional<bool> downstream(std::uint16_t position, int port) const {
        const auto& s = report_.slaves[position];
        if (!s.dl_status_read) return std::nullopt;
        return DlPorts{s.dl_status}.downstream(port);
    }
    bool positions_left() const { return next_ < report_.slaves.size(); }
    bool is_optional_head(std::size_t i) const { return groups_.is_optional(i) && groups_.is_head(i); }
    // A slave that takes its position whatever is there: mandatory, or a member of a group whose head was found.
    bool must_take(std::size_t i) const { return !is_optional_head(i); }

    Verdict judge(std::size_t configured, std::uint16_t position) {
        const auto& slave = eni_.slaves[configured];
        const auto& found = report_.slaves[position];
        Verdict v;
        if (!found.identity) {
            v.match = SlaveMatch::Unreadable;
            return v;
        }
        if (!identity_matches(slave.info, *found.identity)) {
            v.match = SlaveMatch::WrongIdentity;
            return v;
        }
        const auto spec = eni::identification_of(slave);
        if (spec.mode != eni::IdentificationMode::None && spec.mode != eni::IdentificationMode::InputWord) {
            IdentificationCheck check{spec.ado, spec.value, std::nullopt};
            check.read = spec.mode == eni::IdentificationMode::StationAlias ? std::optional<std::uint16_t>(found.alias)
                                                                            : probe_.read(position, spec);
            v.identification = check;
            if (check.read != check.expected) v.match = SlaveMatch::WrongIdentification;
        }
        if (v.match == SlaveMatch::Match && is_optional_head(configured) && !probe_.identify_cmds_pass(position, configured)) {
            v.match = SlaveMatch::WrongIdentification;
            v.identification.reset();  // the IdentifyCmds are what failed
        }
        return v;
    }

    std::optional<std::size_t> floating_candidate(std::uint16_t position) {
        for (const auto& group : groups_.groups()) {
            if (!group.floating || !group.head || decided_[*group.head]) continue;
            if (judge(*group.head, position).match == SlaveMatch::Match) return *group.head;
        }
        return std::nullopt;
    }

    // What an unexpected slave resembles, for its note.
    std::string resemblance(std::uint16_t position) {
        for (std::size_t i = 0; i < eni_.slaves.size(); ++i) {
            if (judge(i, position).match != SlaveMatch::Match) continue;
            const auto& name = eni_.slaves[i].info.name;
            if (result_.position[i]) return fmt::format("duplicate of '{}' (found at position {})", name, *result_.position[i]);
            if (const auto& a = topology_.attachment(i)) {
                return fmt::format("looks like '{}', which belongs at station {} port {}", name,
                                   eni_.slaves[a->parent].info.phys_addr, eni::port_letter(a->port));
            }
            return fmt::format("looks like '{}'", name);
        }
        return {};
    }

    SlaveComparison base(std::size_t configured, std::uint16_t position) const {
        SlaveComparison c;
        c.position = position;
        c.configured = &eni_.slaves[configured];
        c.configured_index = configured;
        c.optional = groups_.is_optional(configured);
        return c;
    }

    // The parent as the bus shows it, when its ports were read; else as the ENI configures it.
    void set_parent(SlaveComparison& c, std::size_t configured, std::optional<std::uint16_t> parent_position,
                    int port) const {
        if (parent_position && report_.slaves[*parent_position].dl_status_read) {
            set_bus_parent(c, parent_position, port);
        } else {
            set_eni_parent(c, configured);
            c.previous_position = parent_position;
        }
    }

    void set_bus_parent(SlaveComparison& c, std::optional<std::uint16_t> parent_position, int port) const {
        if (!parent_position) return;
        c.previous_position = parent_position;
        c.previous_port = eni::port_letter(port);
        c.previous_station = station_at(*parent_position);
    }

    void set_eni_parent(SlaveComparison& c, std::size_t configured) const {
        const auto& a = topology_.attachment(configured);
        if (!a) return;
        c.previous_station = eni_.slaves[a->parent].info.phys_addr;
        // The port only when the ENI names it (a line's "port B of the one before" is not news).
        if (!eni_.slaves[configured].previous_ports.empty()) c.previous_port = eni::port_letter(a->port);
    }

    std::uint16_t station_at(std::uint16_t position) const {
        for (std::size_t i = 0; i < eni_.slaves.size(); ++i) {
            if (result_.position[i] == position) return eni_.slaves[i].info.phys_addr;
        }
        return report_.slaves[position].station_address;
    }

    void decide(std::size_t configured, SlaveComparison c) {
        decided_[configured] = std::move(c);
    }

    // Configured slave `configured` was expected where bus position `q` is.
    void found_at(std::size_t configured, std::optional<std::uint16_t> parent, int port, std::uint16_t q) {
        const auto verdict = judge(configured, q);
        if (verdict.match == SlaveMatch::Match) {
            accept(configured, parent, port, q, verdict);
            return;
        }
        if (const auto floating = floating_candidate(q); floating && *floating != configured) {
            mark_not_found(configured);
            accept(*floating, parent, port, q, judge(*floating, q));
            return;
        }
        if (is_optional_head(configured) && verdict.match == SlaveMatch::WrongIdentity) {
            // Some other device where the group belongs: the group is not here.
            mark_not_found(configured);
            unexpected(q, parent, port, resemblance(q));
            return;
        }
        if (must_take(configured) && verdict.match == SlaveMatch::WrongIdentity && spliced_in_front(configured, q)) {
            // An unknown slave cut into the cable in front of it: the slave behind matches.
            const auto& info = eni_.slaves[configured].info;
            auto note = resemblance(q);
            if (!note.empty()) note += "; ";
            note += fmt::format("cut into the cable in front of '{}' vendor 0x{:08x} product 0x{:08x}, found behind it",
                                info.name, info.vendor_id, info.product_code);
            unexpected(q, parent, port, std::move(note), /*with_subtree=*/false);
            const int next_port = first_downstream_port(q);
            const std::uint16_t r = next_++;
            found_at(configured, q, next_port, r);
            return;
        }
        // The configured slave's place, but not as configured: a mismatch there.
        auto c = base(configured, q);
        c.match = verdict.match;
        c.identification = verdict.identification;
        c.found = &report_.slaves[q];
        set_parent(c, configured, parent, port);
        decide(configured, std::move(c));
        last_found_ = configured;
        visit_children(configured, q);
    }

    int first_downstream_port(std::uint16_t q) const {
        for (const int p : eni::kDownstreamPorts) {
            if (downstream(q, p).value_or(false)) return p;
        }
        return 1;
    }

    // Whether the slave at q has exactly one slave behind it, which matches `configured`.
    bool spliced_in_front(std::size_t configured, std::uint16_t q) {
        if (!report_.slaves[q].dl_status_read || !positions_left()) return false;
        int ports = 0;
        for (const int p : eni::kDownstreamPorts) ports += downstream(q, p).value_or(false) ? 1 : 0;
        if (ports != 1) return false;
        // The slave at q is no configured device, and the one behind it is the
        // expected one. When the expected slave has slaves configured behind it,
        // the bus must have more behind that one too: a wrong device in a line
        // of identical ones would otherwise look like a splice.
        if (!resemblance(q).empty() || judge(configured, next_).match != SlaveMatch::Match) return false;
        const bool configured_has_children = std::any_of(eni::kDownstreamPorts.begin(), eni::kDownstreamPorts.end(),
                                                         [&](int p) { return topology_.child(configured, p).has_value(); });
        if (!configured_has_children) return true;
        const bool more_behind = std::any_of(eni::kDownstreamPorts.begin(), eni::kDownstreamPorts.end(),
                                             [&](int p) { return downstream(next_, p).value_or(false); });
        return more_behind && next_ + 1u < report_.slaves.size();
    }

    void accept(std::size_t configured, std::optional<std::uint16_t> parent, int port, std::uint16_t q,
                const Verdict& verdict) {
        auto c = base(configured, q);
        c.match = SlaveMatch::Match;
        c.identification = verdict.identification;
        c.found = &report_.slaves[q];
        set_parent(c, configured, parent, port);
        result_.position[configured] = q;
        decide(configured, std::move(c));
        last_found_ = configured;
        visit_children(configured, q);
    }

    void visit_children(std::size_t configured, std::uint16_t p) {
        for (const int port : eni::kDownstreamPorts) {
            const auto child = topology_.child(configured, port);
            const auto bus = downstream(p, port);
            if (bus.has_value()) {
                if (!*bus || !positions_left()) {
                    // Nothing there (or the RED side): a configured child may still be behind a break.
                    if (child && !decided_[*child]) unresolved_.push_back(*child);
                    continue;
                }
                const std::uint16_t q = next_++;
                if (child && !decided_[*child]) {
                    found_at(*child, p, port, q);
                } else if (const auto floating = floating_candidate(q)) {
                    accept(*floating, p, port, q, judge(*floating, q));
                } else {
                    unexpected(q, p, port, resemblance(q));
                }
                continue;
            }
            // Ports unknown: follow the ENI.
            if (!child || decided_[*child]) continue;
            if (!positions_left()) {
                unresolved_.push_back(*child);
                continue;
            }
            if (must_take(*child) || judge(*child, next_).match == SlaveMatch::Match) {
                const std::uint16_t q = next_++;
                found_at(*child, p, port, q);
            } else {
                mark_not_found(*child);
            }
        }
    }

    // An unexpected slave at q and everything behind it.
    void unexpected(std::uint16_t q, std::optional<std::uint16_t> parent, int port, std::string note,
                    bool with_subtree = true) {
        SlaveComparison c;
        c.position = q;
        c.match = SlaveMatch::Unexpected;
        c.found = &report_.slaves[q];
        c.note = std::move(note);
        if (parent && report_.slaves[*parent].dl_status_read) {
            set_bus_parent(c, parent, port);
        } else if (last_found_) {
            c.previous_station = eni_.slaves[*last_found_].info.phys_addr;
        }
        unexpected_.push_back(std::move(c));
        if (!with_subtree) return;
        for (const int p : eni::kDownstreamPorts) {
            if (!downstream(q, p).value_or(false) || !positions_left()) continue;
            const std::uint16_t r = next_++;
            unexpected(r, q, p, "behind an unexpected slave");
        }
    }

    // A configured slave (and its configured subtree) that is not on the bus.
    void mark_not_found(std::size_t configured) {
        if (decided_[configured]) return;
        // Where it would be: right behind its parent when the parent is on the bus.
        std::uint16_t where = next_;
        if (const auto& a = topology_.attachment(configured); a && result_.position[a->parent]) {
            where = static_cast<std::uint16_t>(*result_.position[a->parent] + 1);
        }
        auto c = base(configured, where);
        const bool optional = groups_.is_optional(configured);
        // A member of a group whose head is there is missing, not absent.
        const auto group = groups_.group_of(configured);
        const bool head_found = optional && !groups_.is_head(configured) &&
                                result_.position[*groups_.group(group).head].has_value();
        c.match = optional && !head_found ? SlaveMatch::Absent : SlaveMatch::Missing;
        set_eni_parent(c, configured);
        decide(configured, std::move(c));
        for (const int p : eni::kDownstreamPorts) {
            if (const auto child = topology_.child(configured, p)) mark_not_found(*child);
        }
    }

    // Positions no configured port accounted for: fragments behind a line
    // break (matched against the configured slaves still unresolved), floating
    // groups, or unexpected slaves.
    void resolve_leftovers() {
        while (positions_left()) {
            const std::uint16_t q = next_++;
            bool placed = false;
            for (auto it = unresolved_.begin(); it != unresolved_.end(); ++it) {
                if (decided_[*it] || judge(*it, q).match != SlaveMatch::Match) continue;
                const auto slave = *it;
                unresolved_.erase(it);
                accept(slave, std::nullopt, 0, q, judge(slave, q));
                placed = true;
                break;
            }
            if (placed) continue;
            // The fragment may begin further down: the unresolved slave itself is gone
            // (powered off), the slaves configured behind it are reached from the other end.
            if (const auto behind = behind_unresolved(q)) {
                accept(*behind, std::nullopt, 0, q, judge(*behind, q));
                continue;
            }
            if (const auto floating = floating_candidate(q)) {
                accept(*floating, std::nullopt, 0, q, judge(*floating, q));
                continue;
            }
            unexpected(q, std::nullopt, 0, resemblance(q));
        }
    }

    // A slave configured behind an unresolved one (not decided yet) that matches position q.
    std::optional<std::size_t> behind_unresolved(std::uint16_t q) {
        std::vector<std::size_t> stack(unresolved_.rbegin(), unresolved_.rend());
        std::vector<bool> seen(eni_.slaves.size(), false);
        while (!stack.empty()) {
            const auto slave = stack.back();
            stack.pop_back();
            if (seen[slave]) continue;
            seen[slave] = true;
            for (auto port = eni::kDownstreamPorts.rbegin(); port != eni::kDownstreamPorts.rend(); ++port) {
                const auto child = topology_.child(slave, *port);
                if (!child || decided_[*child]) continue;
                stack.push_back(*child);
            }
            const bool is_unresolved = std::find(unresolved_.begin(), unresolved_.end(), slave) != unresolved_.end();
            if (!is_unresolved && !decided_[slave] && judge(slave, q).match == SlaveMatch::Match) return slave;
        }
        return std::nullopt;
    }

    TopologyMatch finish() {
        std::vector<std::size_t> order(eni_.slaves.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [this](std::size_t a, std::size_t b) {
            return eni_.slaves[a].info.ring_position < eni_.slaves[b].info.ring_position;
        });
        for (const auto i : order) result_.comparisons.push_back(*decided_[i]);
        std::stable_sort(unexpected_.begin(), unexpected_.end(),
                         [](const SlaveComparison& a, const SlaveComparison& b) { return a.position < b.position; });
        for (auto& c : unexpected_) result_.comparisons.push_back(std::move(c));

        result_.group_of.resize(eni_.slaves.size());
        for (std::size_t i = 0; i < eni_.slaves.size(); ++i) result_.group_of[i] = groups_.group_of(i);
        result_.groups.assign(groups_.groups().size(), GroupState::Present);
        for (const auto& group : groups_.groups()) {
            bool all_absent = !group.members.empty();
            bool all_match = true;
            for (const auto m : group.members) {
                const auto match = decided_[m]->match;
                all_absent = all_absent && match == SlaveMatch::Absent;
                all_match = all_match && match == SlaveMatch::Match;
            }
            result_.groups[group.number] = all_match ? GroupState::Present
                                           : all_absent ? GroupState::Absent
                                                        : GroupState::Refused;
        }
        return std::move(result_);
    }

    const ScanReport& report_;
    const eni::EniConfig& eni_;
    const eni::HotConnectGroups& groups_;
    IdentificationProbe& probe_;
    eni::EniTopology topology_;
    std::vector<std::optional<SlaveComparison>> decided_;
    std::vector<SlaveComparison> unexpected_;
    std::vector<std::size_t> unresolved_;  // configured slaves whose port showed nothing
    std::optional<std::size_t> last_found_;
    std::uint16_t next_ = 0;
    TopologyMatch result_;
};

}  // namespace

std::optional<std::uint16_t> ReadingsProbe::read(std::uint16_t position, const eni::IdentificationSpec& spec) {
    if (spec.mode != eni::IdentificationMode::ExplicitDeviceId) return std::nullopt;
    if (position >= readings_.explicit_device_ids.size()) return std::nullopt;
    return readings_.explicit_device_ids[position];
}

std::string_view to_string(GroupState state) {
    switch (state) {
        case GroupState::Present: return "present";
        case GroupState::Absent: return "absent";
        case GroupState::Refused: return "refused";
    }
    return "?";
}

std::vector<bool> TopologyMatch::present() const {
    std::vector<bool> result(position.size(), false);
    for (const auto& c : comparisons) {
        if (!c.configured_index || c.match != SlaveMatch::Match) continue;
        result[*c.configured_index] = groups[group_of[*c.configured_index]] == GroupState::Present || !c.optional;
    }
    return result;
}

bool TopologyMatch::blocking() const {
    return std::any_of(comparisons.begin(), comparisons.end(), [](const SlaveComparison& c) {
        return c.match == SlaveMatch::Unexpected || (c.is_mismatch() && !c.optional);
    });
}

TopologyMatch match_topology(const ScanReport& report, const eni::EniConfig& eni, const eni::HotConnectGroups& groups,
                             IdentificationProbe& probe) {
    return Walk(report, eni, groups, probe).run();
}

}  // namespace ecpair::bus
