#pragma once
// The wiring of a simulated EtherCAT segment: which port of which slave is
// plugged into which other port, and where the master's two sides (MAIN and
// RED) attach. The topology knows nothing of ESC behaviour; it answers "what
// is at the other end of this port's cable" and keeps each cable's intact
// flag, so that the segment can carry frames and fake cable faults.
//
// Slaves are indexed 0..n-1 here (file order). Ports are logical ESC ports
// 0..3 (ENI letters A..D). Every cable records its upstream end (towards
// MAIN) and its downstream end, as built from the ENI:
//   - slave 0's port 0 hangs on the MAIN side;
//   - slave i's port 0 hangs on the upstream port named by its PreviousPort,
//     or on port 1 of slave i-1 when it has none (a line); the head of a
//     floating Hot-Connect group hangs nowhere at first (plug() puts it in);
//   - the RED side takes the last slave's port 1 when that is free (the ring's
//     return), else the first free port found walking back from the last
//     slave, each slave's ports in processing order (3, 1, 2) -- slaves not
//     connected to MAIN (a floating group) excepted;
//   - with no slaves at all, MAIN and RED are one cable.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::sim {

enum class Side : std::uint8_t { Main = 0, Red = 1 };
inline constexpr std::size_t kSideCount = 2;
std::string_view to_string(Side side);  // "MAIN" / "RED"

inline constexpr int kPortCount = 4;

// Bit p set: the slave implements logical port p.
using PortMask = std::uint8_t;
inline constexpr PortMask port_bit(int port) { return static_cast<PortMask>(1u << port); }

// The port a frame goes to after port `port` in an ESC (esc-facts.md §3):
// 0 -> (EPU) -> 3 -> 1 -> 2 -> 0. Ports a slave lacks behave as closed, so
// this single order covers 2-, 3- and 4-port ESCs.
constexpr int next_port(int port) {
    constexpr std::array<int, kPortCount> kNext{3, 2, 0, 1};
    return kNext[static_cast<std::size_t>(port)];
}

// "A".."D" for ports 0..3.
char port_letter(int port);

// One end of a cable: a master side or a port of a slave.
struct Endpoint {
    enum class Kind : std::uint8_t { Side, SlavePort };

    Kind kind = Kind::Side;
    Side side = Side::Main;  // when kind == Side
    std::size_t slave = 0;   // when kind == SlavePort (0-based index)
    int port = 0;            // when kind == SlavePort

    static Endpoint of_side(Side s) { return Endpoint{Kind::Side, s, 0, 0}; }
    static Endpoint of_port(std::size_t slave_index, int port_number) {
        return Endpoint{Kind::SlavePort, Side::Main, slave_index, port_number};
    }
    bool is_side() const { return kind == Kind::Side; }

    friend bool operator==(const Endpoint& a, const Endpoint& b) {
        return a.kind == b.kind && (a.is_side() ? a.side == b.side : (a.slave == b.slave && a.port == b.port));
    }
};

// "MAIN", "RED" or "slave 3 port 1" (1-based slave position, as operators count).
std::string describe(const Endpoint& end);

struct Cable {
    Endpoint upstream;
    Endpoint downstream;
    bool intact = true;  // false: cut (`break`), no link at either end
};

// What the topology needs to know of one slave to place it.
struct TopologySlave {
    std::string name;
    std::uint16_t phys_addr = 0;
    PortMask ports = port_bit(0) | port_bit(1);
    std::optional<eni::PreviousPort> previous_port;  // the selected one, if any
    int source_line = 0;                             // where the slave is in the ENI, for errors
    bool floating = false;                           // a floating group's head: not plugged in at first
};

struct TopologyError {
    std::string file;  // empty when the topology does not come from a file
    int line = 0;      // 0 when there is no line to point at
    std::string message;

    // "eni.xml:120: slave 3 'EL2004' (PhysAddr 1003): ..."
    std::string describe() const;
};

class Topology {
public:
    // The ENI rules above. Errors name the slave, its PhysAddr and line.
    static Expected<Topology, TopologyError> from_slaves(std::span<const TopologySlave> slaves);

    // Explicit wiring, for test benches and deliberately odd set-ups (a cable
    // into a port other than 0, a slave with port 0 unconnected). Checked:
    // every endpoint exists, and no endpoint carries two cables.
    static Expected<Topology, TopologyError> from_cables(std::vector<PortMask> slave_ports, std::vector<Cable> cables);

    std::size_t slave_count() const { return slave_ports_.size(); }
    PortMask ports(std::size_t slave) const { return slave_ports_[slave]; }
    bool has_port(std::size_t slave, int port) const { return (slave_ports_[slave] & port_bit(port)) != 0; }

    std::span<const Cable> cables() const { return cables_; }
    const Cable& cable(std::size_t index) const { return cables_[index]; }

    // The cable plugged into `end`, if any.
    std::optional<std::size_t> cable_at(const Endpoint& end) const;
    // The other end of cable `index`, seen from `end` (one of its ends).
    Endpoint peer(std::size_t index, const Endpoint& end) const;

    // The cable "after slave k" as operators count (0 <= k <= n): the one
    // entering port 0 of the slave with index k (k = 0: the MAIN cable of a
    // line), or for k = n the cable of the RED side. nullopt when there is none.
    std::optional<std::size_t> cable_after(std::size_t k) const;

    void set_intact(std::size_t cable, bool intact) { cables_[cable].intact = intact; }

    // Splices a new slave with `ports` (at least 0 and 1) into
    // cable_after(index) -- the cable in front of slave `index`, or the RED
    // cable for index == n -- so that it becomes slave `index`: the old cable
    // now ends at its port 0, a new cable runs from its port 1 to where the
    // old one ended. Later slaves move up by one.
    Expected<void, TopologyError> insert_slave(std::size_t index, PortMask ports);

    // Takes out slave `index`, which must have cables on port 0 and at most
    // port 1: its upstream neighbour is plugged straight into whatever its
    // port 1 reached (the joined cable is intact only if both were).
    Expected<void, TopologyError> remove_slave(std::size_t index);

    // A new cable from `upstream` (a free slave port) to port 0 of `slave`
    // (free too), and taking it out again. unplug() returns where it was.
    Expected<void, TopologyError> plug(const Endpoint& upstream, std::size_t slave);
    Expected<Endpoint, TopologyError> unplug(std::size_t slave);
    // A new slave with `ports` (at least port 0) at index slave_count(), its
    // port 0 plugged into `upstream`.
    Expected<void, TopologyError> attach_slave(PortMask ports, const Endpoint& upstream);

private:
    Topology(std::vector<PortMask> slave_ports, std::vector<Cable> cables);
    void reindex();
    static std::optional<TopologyError> validate(const std::vector<PortMask>& slave_ports,
                                                 const std::vector<Cable>& cables);

    std::vector<PortMask> slave_ports_;
    std::vector<Cable> cables_;
    // Derived lookups, rebuilt by reindex(): cable index per slave port
    // (slave * kPortCount + port) and per side; -1 for nothing plugged in.
    std::vector<int> port_cable_;
    std::array<int, kSideCount> side_cable_{-1, -1};
};

}  // namespace ecpair::sim
