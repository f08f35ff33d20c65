// The wiring rules of Topology: lines, PreviousPort trees, the RED side,
// explicit cables, splicing slaves in and out, and the errors.

#include <catch2/catch.hpp>

#include "ecpair/sim/topology.hpp"

using namespace ecpair;
using namespace ecpair::sim;

namespace {

constexpr PortMask kTwoPorts = port_bit(0) | port_bit(1);
constexpr PortMask kFourPorts = port_bit(0) | port_bit(1) | port_bit(2) | port_bit(3);

TopologySlave slave(std::uint16_t phys_addr, PortMask ports = kTwoPorts,
                    std::optional<eni::PreviousPort> previous = std::nullopt, int line = 0) {
    return TopologySlave{"S" + std::to_string(phys_addr), phys_addr, ports, previous, line};
}

eni::PreviousPort previous(char port, std::uint16_t phys_addr) { return eni::PreviousPort{true, port, phys_addr}; }

Endpoint at(std::size_t slave_index, int port) { return Endpoint::of_port(slave_index, port); }

// The endpoint at the other end of whatever is plugged into `end`.
std::optional<Endpoint> other_end(const Topology& topology, const Endpoint& end) {
    const auto cable = topology.cable_at(end);
    if (!cable) return std::nullopt;
    return topology.peer(*cable, end);
}

}  // namespace

TEST_CASE("a line of slaves: MAIN, port B to port A, RED on the last port B", "[topology]") {
    const std::vector<TopologySlave> slaves{slave(1001), slave(1002), slave(1003), slave(1004), slave(1005)};
    const auto topology = Topology::from_slaves(slaves);
    REQUIRE(topology);
    CHECK(topology->slave_count() == 5);
    CHECK(topology->cables().size() == 6);
    CHECK(other_end(*topology, Endpoint::of_side(Side::Main)) == at(0, 0));
    for (std::size_t i = 0; i + 1 < 5; ++i) CHECK(other_end(*topology, at(i, 1)) == at(i + 1, 0));
    CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(4, 1));

    // cable_after(k) enters slave k+1, and k = n is the RED cable.
    for (std::size_t k = 0; k < 5; ++k) {
        const auto cable = topology->cable_after(k);
        REQUIRE(cable);
        CHECK(topology->cable(*cable).downstream == at(k, 0));
    }
    const auto red = topology->cable_after(5);
    REQUIRE(red);
    CHECK(topology->cable(*red).downstream == Endpoint::of_side(Side::Red));
    CHECK_FALSE(topology->cable_after(6));
}

TEST_CASE("no slaves: MAIN and RED are one cable", "[topology]") {
    const auto topology = Topology::from_slaves({});
    REQUIRE(topology);
    CHECK(other_end(*topology, Endpoint::of_side(Side::Main)) == Endpoint::of_side(Side::Red));
}

TEST_CASE("PreviousPort builds a tree and RED takes the last slave's port B", "[topology]") {
    // A 4-port coupler with slaves on its ports D, B and C.
    const std::vector<TopologySlave> slaves{
        slave(1001, kFourPorts),
        slave(1002, kTwoPorts, previous('D', 1001)),
        slave(1003, kTwoPorts, previous('B', 1001)),
        slave(1004, kTwoPorts, previous('C', 1001)),
    };
    const auto topology = Topology::from_slaves(slaves);
    REQUIRE(topology);
    CHECK(other_end(*topology, at(1, 0)) == at(0, 3));
    CHECK(other_end(*topology, at(2, 0)) == at(0, 1));
    CHECK(other_end(*topology, at(3, 0)) == at(0, 2));
    CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(3, 1));
    CHECK_FALSE(other_end(*topology, at(1, 1)));
}

TEST_CASE("RED falls back to the first free port at the end of the line", "[topology]") {
    // The last slave has one port only: RED goes to the previous slave's free port D.
    const std::vector<TopologySlave> slaves{
        slave(1, port_bit(0) | port_bit(1) | port_bit(3)),
        slave(2, port_bit(0)),
    };
    const auto topology = Topology::from_slaves(slaves);
    REQUIRE(topology);
    CHECK(other_end(*topology, at(1, 0)) == at(0, 1));
    CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(0, 3));
}

TEST_CASE("with no free port at all RED stays unconnected", "[topology]") {
    const std::vector<TopologySlave> slaves{slave(1), slave(2, port_bit(0))};
    const auto topology = Topology::from_slaves(slaves);
    REQUIRE(topology);
    CHECK_FALSE(topology->cable_at(Endpoint::of_side(Side::Red)));
    CHECK_FALSE(topology->cable_after(2));
}

TEST_CASE("PreviousPort errors name the slave, the port and the line", "[topology]") {
    SECTION("an unknown PhysAddr") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('B', 4711), 77)};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK(topology.error().line == 77);
        CHECK(topology.error().message ==
              "slave 2 'S1002' (PhysAddr 1002): PreviousPort names PhysAddr 4711, which no slave has");
        CHECK(topology.error().describe() == "line 77: " + topology.error().message);
    }
    SECTION("a slave later in the file") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('B', 1003)), slave(1003)};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::Contains("PhysAddr 1003, which is not a slave before it"));
    }
    SECTION("a port the upstream slave does not have") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('C', 1001))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK(topology.error().message ==
              "slave 2 'S1002' (PhysAddr 1002): its upstream port C of slave 1 'S1001' (PhysAddr 1001) does not "
              "exist (that slave has ports A, B)");
    }
    SECTION("a port already taken") {
        const std::vector<TopologySlave> slaves{slave(1001, kFourPorts), slave(1002, kTwoPorts, previous('D', 1001)),
                                                slave(1003, kTwoPorts, previous('D', 1001))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK(topology.error().message ==
              "slave 3 'S1003' (PhysAddr 1003): its upstream port D of slave 1 'S1001' (PhysAddr 1001) is already "
              "connected to slave 2 'S1002' (PhysAddr 1002)");
    }
    SECTION("port A of the upstream slave is its own way to MAIN") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('A', 1001))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::Contains("is already connected to the MAIN side"));
    }
    SECTION("a port letter beyond D") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('E', 1001))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::Contains("port 'E', which is not one of A..D"));
    }
    SECTION("the default line runs into a taken port B") {
        // Slave 2 hangs on port B of slave 1 by PreviousPort, slave 3 has none: it wants slave 2's B, which is free;
        // slave 4 then names slave 1's B again.
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, kTwoPorts, previous('B', 1001)), slave(1003),
                                                slave(1004, kTwoPorts, previous('B', 1001))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::StartsWith("slave 4 'S1004'"));
    }
    SECTION("a slave without port A") {
        const std::vector<TopologySlave> slaves{slave(1001), slave(1002, port_bit(1))};
        const auto topology = Topology::from_slaves(slaves);
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::Contains("has no port A"));
    }
}

TEST_CASE("explicit cables are validated", "[topology]") {
    const std::vector<PortMask> ports{kTwoPorts, kTwoPorts};
    SECTION("a port that does not exist") {
        const auto topology = Topology::from_cables(ports, {Cable{at(0, 1), at(1, 2), true}});
        REQUIRE_FALSE(topology);
        CHECK(topology.error().message ==
              "a cable names slave 2 port 2, which does not exist (that slave has ports A, B)");
    }
    SECTION("a slave that does not exist") {
        const auto topology = Topology::from_cables(ports, {Cable{at(0, 1), at(2, 0), true}});
        REQUIRE_FALSE(topology);
        CHECK_THAT(topology.error().message, Catch::Contains("slave 3, but there are only 2 slaves"));
    }
    SECTION("two cables on one port") {
        const auto topology = Topology::from_cables(
            ports, {Cable{Endpoint::of_side(Side::Main), at(0, 0), true}, Cable{at(1, 1), at(0, 0), true}});
        REQUIRE_FALSE(topology);
        CHECK(topology.error().message == "slave 1 port 0 carries two cables");
    }
    SECTION("two cables on one side") {
        const auto topology = Topology::from_cables(ports, {Cable{Endpoint::of_side(Side::Main), at(0, 0), true},
                                                            Cable{Endpoint::of_side(Side::Main), at(1, 0), true}});
        REQUIRE_FALSE(topology);
        CHECK(topology.error().message == "MAIN carries two cables");
    }
    SECTION("a valid odd wiring is kept as given") {
        const auto topology = Topology::from_cables(
            ports, {Cable{Endpoint::of_side(Side::Main), at(0, 0), true}, Cable{at(0, 1), at(1, 1), true}});
        REQUIRE(topology);
        CHECK(other_end(*topology, at(1, 1)) == at(0, 1));
        CHECK_FALSE(topology->cable_at(at(1, 0)));
    }
}

TEST_CASE("a slave spliced in and taken out again", "[topology]") {
    const std::vector<TopologySlave> slaves{slave(1), slave(2), slave(3)};
    auto topology = Topology::from_slaves(slaves);
    REQUIRE(topology);

    SECTION("in the middle") {
        REQUIRE(topology->insert_slave(1, kTwoPorts));
        CHECK(topology->slave_count() == 4);
        CHECK(other_end(*topology, at(0, 1)) == at(1, 0));
        CHECK(other_end(*topology, at(1, 1)) == at(2, 0));
        CHECK(other_end(*topology, at(2, 1)) == at(3, 0));
        CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(3, 1));

        REQUIRE(topology->remove_slave(1));
        CHECK(topology->slave_count() == 3);
        CHECK(other_end(*topology, at(0, 1)) == at(1, 0));
        CHECK(other_end(*topology, at(1, 1)) == at(2, 0));
        CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(2, 1));
        CHECK(topology->cables().size() == 4);
    }
    SECTION("first and last") {
        REQUIRE(topology->insert_slave(0, kTwoPorts));
        CHECK(other_end(*topology, Endpoint::of_side(Side::Main)) == at(0, 0));
        CHECK(other_end(*topology, at(0, 1)) == at(1, 0));
        REQUIRE(topology->insert_slave(4, kTwoPorts));
        CHECK(other_end(*topology, at(3, 1)) == at(4, 0));
        CHECK(other_end(*topology, Endpoint::of_side(Side::Red)) == at(4, 1));
    }
    SECTION("a cut cable stays cut on its upstream part, and a joined cable is cut if either part was") {
        topology->set_intact(*topology->cable_after(1), false);
        REQUIRE(topology->insert_slave(1, kTwoPorts));
        CHECK_FALSE(topology->cable(*topology->cable_after(1)).intact);
        CHECK(topology->cable(*topology->cable_after(2)).intact);
        REQUIRE(topology->remove_slave(1));
        CHECK_FALSE(topology->cable(*topology->cable_after(1)).intact);
    }
    SECTION("out of range, and slaves that are not in a line") {
        CHECK_FALSE(topology->insert_slave(4, kTwoPorts));
        CHECK_FALSE(topology->insert_slave(0, port_bit(0)));
        CHECK_FALSE(topology->remove_slave(3));
        auto tree = Topology::from_slaves(std::vector<TopologySlave>{
            slave(1, kFourPorts), slave(2, kTwoPorts, previous('D', 1)), slave(3, kTwoPorts, previous('B', 1))});
        REQUIRE(tree);
        const auto refused = tree->remove_slave(0);
        REQUIRE_FALSE(refused);
        CHECK(refused.error().message == "slave 1 has a cable on port D; only a slave in a line can be taken out");
    }
}

TEST_CASE("the ESC processing order", "[topology]") {
    CHECK(next_port(0) == 3);
    CHECK(next_port(3) == 1);
    CHECK(next_port(1) == 2);
    CHECK(next_port(2) == 0);
}
