// Building and changing the wiring of a simulated segment.
//
// from_slaves() walks the slaves in file order and plugs each one's port 0
// into its upstream port (PreviousPort, or the previous slave's port 1),
// checking that the upstream slave exists earlier in the file, has that port
// and has not already used it. Then the RED side takes the ring's return
// port. from_cables() takes a ready wiring and only validates it.
//
// The cable list is the single source of truth; the per-port lookup table is
// derived from it (reindex()) after every change, which only happens on
// operator faults, never per frame.

#include "ecpair/sim/topology.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace ecpair::sim {

namespace {

std::string ports_as_letters(PortMask ports) {
    std::string letters;
    for (int p = 0; p < kPortCount; ++p) {
        if ((ports & port_bit(p)) != 0) {
            if (!letters.empty()) letters += ", ";
            letters += port_letter(p);
        }
    }
    return letters.empty() ? std::string("none") : letters;
}

std::string slave_label(const TopologySlave& slave, std::size_t index) {
    return fmt::format("slave {} '{}' (PhysAddr {})", index + 1, slave.name, slave.phys_addr);
}

TopologyError slave_error(const TopologySlave& slave, std::size_t index, std::string what) {
    return TopologyError{{}, slave.source_line, fmt::format("{}: {}", slave_label(slave, index), what)};
}

// The ports a frame leaves by after the EPU, in processing order.
constexpr std::array<int, 3> kDownstreamOrder{3, 1, 2};

using PortOwners = std::vector<std::array<std::optional<std::string>, kPortCount>>;

// The slave index with this PhysAddr among slaves[0, before), or why there is none.
Expected<std::size_t, TopologyError> earlier_slave(std::span<const TopologySlave> slaves, std::size_t before,
                                                   std::uint16_t phys_addr) {
    std::optional<std::size_t> found;
    std::size_t matches = 0;
    for (std::size_t j = 0; j < before; ++j) {
        if (slaves[j].phys_addr == phys_addr) {
            found = j;
            ++matches;
        }
    }
    const auto& slave = slaves[before];
    if (!found) {
        const bool later = std::any_of(slaves.begin() + static_cast<std::ptrdiff_t>(before), slaves.end(),
                                       [&](const TopologySlave& s) { return s.phys_addr == phys_addr; });
        return unexpected(slave_error(
            slave, before,
            later ? fmt::format("PreviousPort names PhysAddr {}, which is not a slave before it in the file", phys_addr)
                  : fmt::format("PreviousPort names PhysAddr {}, which no slave has", phys_addr)));
    }
    if (matches > 1) {
        return unexpected(slave_error(
            slave, before,
            fmt::format("PreviousPort names PhysAddr {}, which {} earlier slaves share", phys_addr, matches)));
    }
    return *found;
}

// The port slave i hangs on: its PreviousPort, or port B of slave i-1;
// checked to exist and to be free.
Expected<Endpoint, TopologyError> upstream_port_of(std::span<const TopologySlave> slaves, std::size_t i,
                                                   const PortOwners& taken_by) {
    const auto& slave = slaves[i];
    std::size_t upstream = i - 1;
    int port = 1;
    if (slave.previous_port) {
        const auto& previous = *slave.previous_port;
        if (previous.port < 'A' || previous.port > 'D') {
            return unexpected(slave_error(
                slave, i, fmt::format("PreviousPort names port '{}', which is not one of A..D", previous.port)));
        }
        port = previous.port - 'A';
        const auto found = earlier_slave(slaves, i, previous.phys_addr);
        if (!found) return unexpected(found.error());
        upstream = *found;
    }
    const auto& up = slaves[upstream];
    if ((up.ports & port_bit(port)) == 0) {
        return unexpected(
            slave_error(slave, i,
                        fmt::format("its upstream port {} of {} does not exist (that slave has ports {})",
                                    port_letter(port), slave_label(up, upstream), ports_as_letters(up.ports))));
    }
    if (const auto& owner = taken_by[upstream][static_cast<std::size_t>(port)]) {
        return unexpected(slave_error(slave, i,
                                      fmt::format("its upstream port {} of {} is already connected to {}",
                                                  port_letter(port), slave_label(up, upstream), *owner)));
    }
    return Endpoint::of_port(upstream, port);
}

// The ring's return: the last slave's port B when free, else the first free
// port walking back from the end of the line; nullopt when all are taken.
std::optional<Endpoint> red_port(std::span<const TopologySlave> slaves, const PortOwners& taken_by,
                                 const std::vector<bool>& connected) {
    std::size_t last = slaves.size();
    while (last > 0 && !connected[last - 1]) --last;
    if (last == 0) return std::nullopt;
    --last;
    if ((slaves[last].ports & port_bit(1)) != 0 && !taken_by[last][1]) return Endpoint::of_port(last, 1);
    for (std::size_t k = last + 1; k-- > 0;) {
        if (!connected[k]) continue;
        for (const int p : kDownstreamOrder) {
            if ((slaves[k].ports & port_bit(p)) != 0 && !taken_by[k][static_cast<std::size_t>(p)]) {
                return Endpoint::of_port(k, p);
            }
        }
    }
    return std::nullopt;
}

}  // namespace

std::string_view to_string(Side side) { return side == Side::Main ? "MAIN" : "RED"; }

char port_letter(int port) { return static_cast<char>('A' + port); }

std::string describe(const Endpoint& end) {
    if (end.is_side()) return std::string(to_string(end.side));
    return fmt::format("slave {} port {}", end.slave + 1, end.port);
}

std::string TopologyError::describe() const {
    if (file.empty()) return line > 0 ? fmt::format("line {}: {}", line, message) : message;
    return line > 0 ? fmt::format("{}:{}: {}", file, line, message) : fmt::format("{}: {}", file, message);
}

Topology::Topology(std::vector<PortMask> slave_ports, std::vector<Cable> cables)
    : slave_ports_(std::move(slave_ports)), cables_(std::move(cables)) {
    reindex();
}

Expected<Topology, TopologyError> Topology::from_slaves(std::span<const TopologySlave> slaves) {
    std::vector<PortMask> ports;
    ports.reserve(slaves.size());
    for (const auto& slave : slaves) ports.push_back(slave.ports);

    std::vector<Cable> cables;
    if (slaves.empty()) {
        cables.push_back(Cable{Endpoint::of_side(Side::Main), Endpoint::of_side(Side::Red), true});
        return Topology(std::move(ports), std::move(cables));
    }

    // taken_by[i][p]: what hangs on port p of slave i, for the error message.
    PortOwners taken_by(slaves.size());
    std::vector<bool> connected(slaves.size(), false);  // reachable from MAIN
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        const auto& slave = slaves[i];
        if ((slave.ports & port_bit(0)) == 0) {
            return unexpected(slave_error(slave, i, "has no port A (0), so it cannot be connected upstream"));
        }
        if (i == 0) {
            // The first slave's PreviousPort, if any, would name the master: it always hangs on MAIN.
            cables.push_back(Cable{Endpoint::of_side(Side::Main), Endpoint::of_port(0, 0), true});
            taken_by[0][0] = "the MAIN side";
            connected[0] = true;
            continue;
        }
        if (slave.floating) continue;
        const auto upstream = upstream_port_of(slaves, i, taken_by);
        if (!upstream) return unexpected(upstream.error());
        taken_by[upstream->slave][static_cast<std::size_t>(upstream->port)] = slave_label(slave, i);
        cables.push_back(Cable{*upstream, Endpoint::of_port(i, 0), true});
        connected[i] = connected[upstream->slave];
    }
    if (const auto red = red_port(slaves, taken_by, connected)) {
        cables.push_back(Cable{*red, Endpoint::of_side(Side::Red), true});
    }
    return Topology(std::move(ports), std::move(cables));
}

std::optional<TopologyError> Topology::validate(const std::vector<PortMask>& slave_ports,
                                                const std::vector<Cable>& cables) {
    std::vector<const Cable*> port_owner(slave_ports.size() * kPortCount, nullptr);
    std::array<const Cable*, kSideCount> side_owner{nullptr, nullptr};
    for (const auto& cable : cables) {
        if (cable.upstream == cable.downstream) {
            return TopologyError{{}, 0, fmt::format("a cable connects {} to itself", describe(cable.upstream))};
        }
        for (const Endpoint* end : {&cable.upstream, &cable.downstream}) {
            const Cable** owner = nullptr;
            if (end->is_side()) {
                owner = &side_owner[static_cast<std::size_t>(end->side)];
            } else {
                if (end->slave >= slave_ports.size()) {
                    return TopologyError{{},
                                         0,
                                         fmt::format("a cable names slave {}, but there are only {} slaves",
                                                     end->slave + 1, slave_ports.size())};
                }
                if (end->port < 0 || end->port >= kPortCount || (slave_ports[end->slave] & port_bit(end->port)) == 0) {
                    return TopologyError{{},
                                         0,
                                         fmt::format("a cable names {}, which does not exist (that slave has ports {})",
                                                     describe(*end), ports_as_letters(slave_ports[end->slave]))};
                }
                owner = &port_owner[end->slave * kPortCount + static_cast<std::size_t>(end->port)];
            }
            if (*owner != nullptr) {
                return TopologyError{{}, 0, fmt::format("{} carries two cables", describe(*end))};
            }
            *owner = &cable;
        }
    }
    return std::nullopt;
}

Expected<Topology, TopologyError> Topology::from_cables(std::vector<PortMask> slave_ports, std::vector<Cable> cables) {
    if (auto error = validate(slave_ports, cables)) return unexpected(std::move(*error));
    return Topology(std::move(slave_ports), std::move(cables));
}

void Topology::reindex() {
    port_cable_.assign(slave_ports_.size() * kPortCount, -1);
    side_cable_ = {-1, -1};
    for (std::size_t c = 0; c < cables_.size(); ++c) {
        for (const Endpoint* end : {&cables_[c].upstream, &cables_[c].downstream}) {
            int& slot = end->is_side() ? side_cable_[static_cast<std::size_t>(end->side)]
                                       : port_cable_[end->slave * kPortCount + static_cast<std::size_t>(end->port)];
            slot = static_cast<int>(c);
        }
    }
}

std::optional<std::size_t> Topology::cable_at(const Endpoint& end) const {
    const int index = end.is_side() ? side_cable_[static_cast<std::size_t>(end.side)]
                                    : port_cable_[end.slave * kPortCount + static_cast<std::size_t>(end.port)];
    if (index < 0) return std::nullopt;
    return static_cast<std::size_t>(index);
}

Endpoint Topology::peer(std::size_t index, const Endpoint& end) const {
    const Cable& cable = cables_[index];
    return cable.upstream == end ? cable.downstream : cable.upstream;
}

std::optional<std::size_t> Topology::cable_after(std::size_t k) const {
    if (k < slave_count()) return cable_at(Endpoint::of_port(k, 0));
    if (k == slave_count()) return cable_at(Endpoint::of_side(Side::Red));
    return std::nullopt;
}

Expected<void, TopologyError> Topology::insert_slave(std::size_t index, PortMask ports) {
    if (index > slave_count()) {
        return unexpected(TopologyError{
            {}, 0, fmt::format("cannot insert a slave at position {}: there are {} slaves", index + 1, slave_count())});
    }
    if ((ports & port_bit(0)) == 0 || (ports & port_bit(1)) == 0) {
        return unexpected(TopologyError{{}, 0, "an inserted slave needs ports A and B"});
    }
    const auto spliced = cable_after(index);
    if (!spliced) {
        return unexpected(TopologyError{{},
                                        0,
                                        index < slave_count()
                                            ? fmt::format("slave {} has no cable on port A to insert into", index + 1)
                                            : std::string("the RED side has no cable to insert into")});
    }
    // Later slaves move up by one; then the spliced cable ends at the new slave.
    for (auto& cable : cables_) {
        for (Endpoint* end : {&cable.upstream, &cable.downstream}) {
            if (!end->is_side() && end->slave >= index) ++end->slave;
        }
    }
    slave_ports_.insert(slave_ports_.begin() + static_cast<std::ptrdiff_t>(index), ports);
    Cable& old = cables_[*spliced];
    const Endpoint old_downstream = old.downstream;
    old.downstream = Endpoint::of_port(index, 0);
    cables_.push_back(Cable{Endpoint::of_port(index, 1), old_downstream, true});
    reindex();
    return {};
}

Expected<void, TopologyError> Topology::remove_slave(std::size_t index) {
    if (index >= slave_count()) {
        return unexpected(TopologyError{{}, 0, fmt::format("there is no slave {}", index + 1)});
    }
    const auto in = cable_at(Endpoint::of_port(index, 0));
    const auto out = has_port(index, 1) ? cable_at(Endpoint::of_port(index, 1)) : std::nullopt;
    for (int p : {2, 3}) {
        if (has_port(index, p) && cable_at(Endpoint::of_port(index, p))) {
            return unexpected(
                TopologyError{{},
                              0,
                              fmt::format("slave {} has a cable on port {}; only a slave in a line can be taken out",
                                          index + 1, port_letter(p))});
        }
    }
    if (!in) {
        return unexpected(TopologyError{{}, 0, fmt::format("slave {} has no cable on port A", index + 1)});
    }

    const Endpoint self_in = Endpoint::of_port(index, 0);
    if (out) {
        Cable& joined = cables_[*in];
        const Cable& tail = cables_[*out];
        const Endpoint far_end = tail.upstream == Endpoint::of_port(index, 1) ? tail.downstream : tail.upstream;
        (joined.upstream == self_in ? joined.upstream : joined.downstream) = far_end;
        joined.intact = joined.intact && tail.intact;
        cables_.erase(cables_.begin() + static_cast<std::ptrdiff_t>(*out));
    } else {
        cables_.erase(cables_.begin() + static_cast<std::ptrdiff_t>(*in));
    }
    slave_ports_.erase(slave_ports_.begin() + static_cast<std::ptrdiff_t>(index));
    for (auto& cable : cables_) {
        for (Endpoint* end : {&cable.upstream, &cable.downstream}) {
            if (!end->is_side() && end->slave > index) --end->slave;
        }
    }
    reindex();
    return {};
}

Expected<void, TopologyError> Topology::plug(const Endpoint& upstream, std::size_t slave) {
    if (slave >= slave_count()) return unexpected(TopologyError{{}, 0, fmt::format("there is no slave {}", slave + 1)});
    if (!upstream.is_side() && (upstream.slave >= slave_count() || !has_port(upstream.slave, upstream.port))) {
        return unexpected(TopologyError{{}, 0, fmt::format("{} does not exist", describe(upstream))});
    }
    if (upstream == Endpoint::of_port(slave, 0)) {
        return unexpected(TopologyError{{}, 0, "a slave cannot be plugged into itself"});
    }
    if (cable_at(upstream)) return unexpected(TopologyError{{}, 0, fmt::format("{} already has a cable", describe(upstream))});
    if (cable_at(Endpoint::of_port(slave, 0))) {
        return unexpected(TopologyError{{}, 0, fmt::format("slave {} port A already has a cable", slave + 1)});
    }
    cables_.push_back(Cable{upstream, Endpoint::of_port(slave, 0), true});
    reindex();
    return {};
}

Expected<Endpoint, TopologyError> Topology::unplug(std::size_t slave) {
    if (slave >= slave_count()) return unexpected(TopologyError{{}, 0, fmt::format("there is no slave {}", slave + 1)});
    const Endpoint port0 = Endpoint::of_port(slave, 0);
    const auto cable = cable_at(port0);
    if (!cable) return unexpected(TopologyError{{}, 0, fmt::format("slave {} is not plugged in", slave + 1)});
    const Endpoint upstream = peer(*cable, port0);
    cables_.erase(cables_.begin() + static_cast<std::ptrdiff_t>(*cable));
    reindex();
    return upstream;
}

Expected<void, TopologyError> Topology::attach_slave(PortMask ports, const Endpoint& upstream) {
    if ((ports & port_bit(0)) == 0) return unexpected(TopologyError{{}, 0, "an attached slave needs port A"});
    if (!upstream.is_side() && (upstream.slave >= slave_count() || !has_port(upstream.slave, upstream.port))) {
        return unexpected(TopologyError{{}, 0, fmt::format("{} does not exist", describe(upstream))});
    }
    if (cable_at(upstream)) return unexpected(TopologyError{{}, 0, fmt::format("{} already has a cable", describe(upstream))});
    slave_ports_.push_back(ports);
    cables_.push_back(Cable{upstream, Endpoint::of_port(slave_ports_.size() - 1, 0), true});
    reindex();
    return {};
}

}  // namespace ecpair::sim
