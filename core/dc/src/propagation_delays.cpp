// Propagation delays from receive-time latches (see the header for the
// physics). Latches are 32-bit local times: only differences within one
// slave are taken, in 32-bit arithmetic, so a clock that wrapped between
// two latches costs nothing.

#include "ecpair/dc/propagation_delays.hpp"

#include <fmt/format.h>

namespace ecpair::dc {
namespace {

// The time from `from` to `to` on one slave's 32-bit clock.
std::int64_t between(std::uint32_t from, std::uint32_t to) {
    return static_cast<std::int64_t>(static_cast<std::int32_t>(to - from));
}

// A slave's open ports in the order the frame visits them, the entry port first.
std::vector<int> visit_order(const LatchedSlave& s) {
    std::vector<int> order{s.entry_port};
    for (int p = next_port(s.entry_port); p != s.entry_port; p = next_port(p)) {
        if (s.open[static_cast<std::size_t>(p)]) order.push_back(p);
    }
    return order;
}

// What one slave's latches say, relative to the frame's arrival at its entry port.
struct LocalTimes {
    std::array<std::int64_t, kPorts> departure{};  // when the frame left by each open port
    std::array<std::int64_t, kPorts> behind{};     // how long it stayed behind each open port
    std::int64_t in_tree = 0;                      // how long it stayed in the slave's tree
    std::int64_t processing = 0;                   // when it reached the processing unit
};

LocalTimes local_times(const LatchedSlave& s) {
    LocalTimes t;
    const auto order = visit_order(s);
    const auto entry = s.port_time[static_cast<std::size_t>(s.entry_port)];
    std::int64_t previous = 0;
    for (std::size_t i = 1; i < order.size(); ++i) {
        const auto p = static_cast<std::size_t>(order[i]);
        const std::int64_t back = between(entry, s.port_time[p]);
        t.departure[p] = previous;
        t.behind[p] = back - previous;
        previous = back;
    }
    t.in_tree = previous;
    t.processing = between(entry, static_cast<std::uint32_t>(s.processing_time));
    return t;
}

struct Child {
    int port;
    std::size_t index;
};

}  // namespace

int next_port(int port) {
    switch (port) {
        case 0: return 3;
        case 3: return 1;
        case 1: return 2;
        default: return 0;
    }
}

Expected<std::vector<SlaveDelay>, std::string> propagation_delays(const std::vector<LatchedSlave>& slaves,
                                                                  std::size_t reference) {
    const std::size_t n = slaves.size();
    if (reference >= n) return unexpected(fmt::format("reference clock {} is not among the {} slaves", reference, n));
    if (!slaves[reference].has_dc)
        return unexpected(fmt::format("the reference clock (slave {}) has no DC unit", reference));

    // The tree: one root, every parent's port used once and open.
    std::optional<std::size_t> root;
    std::vector<std::vector<Child>> children(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& s = slaves[i];
        if (!s.parent) {
            if (root) return unexpected(fmt::format("slaves {} and {} both have no parent: not one tree", *root, i));
            root = i;
            continue;
        }
        if (*s.parent >= n || *s.parent == i)
            return unexpected(fmt::format("slave {}: parent {} does not exist", i, *s.parent));
        if (s.parent_port < 0 || s.parent_port >= kPorts || s.entry_port < 0 || s.entry_port >= kPorts) {
            return unexpected(fmt::format("slave {}: port out of range", i));
        }
        const auto& parent = slaves[*s.parent];
        if (!parent.open[static_cast<std::size_t>(s.parent_port)] || parent.entry_port == s.parent_port) {
            return unexpected(fmt::format("slave {} hangs on port {} of slave {}, which does not lead on", i,
                                          s.parent_port, *s.parent));
        }
        for (const auto& c : children[*s.parent]) {
            if (c.port == s.parent_port) {
                return unexpected(fmt::format("slaves {} and {} both hang on port {} of slave {}", c.index, i,
                                              s.parent_port, *s.parent));
            }
        }
        children[*s.parent].push_back(Child{s.parent_port, i});
    }
    if (!root) return unexpected(std::string("no slave is where the frame entered: not a tree"));

    std::vector<LocalTimes> local(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (slaves[i].has_dc) local[i] = local_times(slaves[i]);
    }

    // Walk from the root. Each slave carries the DC slave whose times measure
    // its way from the root (`anchor`, through slaves without DC unit that
    // only pass the frame on) and that anchor's port the way starts at.
    struct Way {
        std::optional<std::size_t> anchor;  // nullopt: no DC slave before it yet
        int port = 0;
        std::string broken;  // why the way cannot be measured
    };
    std::vector<SlaveDelay> result(n);
    std::vector<std::optional<std::int64_t>> arrival(n);  // entry port, common time axis
    std::vector<bool> seen(n, false);
    std::vector<std::pair<std::size_t, Way>> stack{{*root, Way{}}};
    while (!stack.empty()) {
        const auto [i, way] = stack.back();
        stack.pop_back();
        if (seen[i]) return unexpected(fmt::format("slave {} is reached twice: not a tree", i));
        seen[i] = true;
        const auto& s = slaves[i];
        if (s.has_dc) {
            if (!way.broken.empty()) {
                result[i].why = way.broken;
            } else if (!way.anchor) {
                arrival[i] = 0;  // the first DC slave on the way from the entry sets the time axis
            } else if (arrival[*way.anchor]) {
                const auto& a = local[*way.anchor];
                const auto port = static_cast<std::size_t>(way.port);
                const std::int64_t cable = (a.behind[port] - local[i].in_tree) / 2;
                result[i].cable = cable;
                arrival[i] = *arrival[*way.anchor] + a.departure[port] + cable;
            } else {
                result[i].why = result[*way.anchor].why;
            }
        }
        for (const auto& c : children[i]) {
            Way next = way;
            if (s.has_dc) {
                next = Way{i, c.port, {}};
            } else if (children[i].size() > 1 && way.broken.empty()) {
                next.broken = fmt::format("behind slave {}, which has no DC unit and more than one port leading on", i);
            }
            stack.emplace_back(c.index, next);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!seen[i]) return unexpected(fmt::format("slave {} cannot be reached from the entry: not one tree", i));
    }
    if (!arrival[reference]) {
        return unexpected(
            fmt::format("the reference clock (slave {}) cannot be measured: {}", reference, result[reference].why));
    }
    const std::int64_t reference_time = *arrival[reference] + local[reference].processing;
    for (std::size_t i = 0; i < n; ++i) {
        if (!slaves[i].has_dc) {
            result[i].why = "no DC unit";
        } else if (arrival[i]) {
            result[i].delay = *arrival[i] + local[i].processing - reference_time;
        }
    }
    return result;
}

Expected<SegmentTree, std::string> tree_from_ports(const std::vector<std::array<bool, kPorts>>& open) {
    SegmentTree tree;
    tree.attachment.resize(open.size());
    if (open.empty()) return tree;
    struct Visit {
        std::size_t position;
        int next;  // the port to look at next; 0 when every port was looked at
    };
    std::vector<Visit> stack{{0, next_port(0)}};
    const auto take_port = [&open](Visit& v) -> std::optional<int> {
        while (v.next != 0) {
            const int p = v.next;
            v.next = next_port(p);
            if (open[v.position][static_cast<std::size_t>(p)]) return p;
        }
        return std::nullopt;
    };
    for (std::size_t i = 1; i < open.size(); ++i) {
        bool placed = false;
        while (!stack.empty() && !placed) {
            if (const auto port = take_port(stack.back())) {
                tree.attachment[i] = Attachment{stack.back().position, *port};
                stack.push_back(Visit{i, next_port(0)});
                placed = true;
            } else {
                stack.pop_back();
            }
        }
        if (!placed) {
            return unexpected(
                fmt::format("position {} hangs on no open port of the slaves before it (DL status and "
                            "slave count disagree)",
                            i));
        }
    }
    while (!stack.empty()) {
        while (const auto port = take_port(stack.back())) tree.exits.push_back(PortRef{stack.back().position, *port});
        stack.pop_back();
    }
    return tree;
}

std::vector<LatchedSlave> orient(const SegmentTree& tree, std::size_t entry, int entry_port) {
    const std::size_t n = tree.attachment.size();
    // Cables between slaves, both ends: (port, neighbour, the neighbour's port).
    struct End {
        int port;
        std::size_t neighbour;
        int neighbour_port;
    };
    std::vector<std::vector<End>> cables(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (const auto& a = tree.attachment[i]) {
            cables[i].push_back(End{0, a->parent, a->port});
            cables[a->parent].push_back(End{a->port, i, 0});
        }
    }
    std::vector<LatchedSlave> slaves(n);
    if (entry >= n) return slaves;
    std::vector<bool> seen(n, false);
    std::vector<std::size_t> queue{entry};
    slaves[entry].entry_port = entry_port;
    seen[entry] = true;
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::size_t i = queue[q];
        auto& s = slaves[i];
        s.open[static_cast<std::size_t>(s.entry_port)] = true;
        for (const auto& end : cables[i]) {
            s.open[static_cast<std::size_t>(end.port)] = true;
            if (seen[end.neighbour]) continue;
            seen[end.neighbour] = true;
            auto& child = slaves[end.neighbour];
            child.parent = i;
            child.parent_port = end.port;
            child.entry_port = end.neighbour_port;
            queue.push_back(end.neighbour);
        }
    }
    return slaves;
}

}  // namespace ecpair::dc
