// Propagation delays from synthetic latches: a small model of the wire walks
// a frame through a tree of slaves (cables with known delays, clocks with
// unrelated offsets that wrap at 32 bits), writes each slave's latches as an
// ESC would, and the computed delays must be exactly the model's: lines,
// junctions (EK1122), open ports with nothing behind them, a line entered
// from its far end, slaves without DC unit.

#include <catch2/catch.hpp>

#include "ecpair/dc/propagation_delays.hpp"

using namespace ecpair;
using namespace ecpair::dc;

namespace {

// The segment as the model knows it: for each slave its cable delay (to its
// parent) and the offset of its local clock to the true time.
struct Model {
    std::vector<LatchedSlave> slaves;  // tree and open ports; latches written by run()
    std::vector<std::int64_t> cable;   // per slave: one-way delay to its parent
    std::vector<std::uint64_t> clock_offset;
    std::vector<std::int64_t> processed_at;  // true time at the processing unit

    // The child on `port` of `v`.
    std::optional<std::size_t> child(std::size_t v, int port) const {
        for (std::size_t i = 0; i < slaves.size(); ++i) {
            if (slaves[i].parent == v && slaves[i].parent_port == port) return i;
        }
        return std::nullopt;
    }

    void latch(std::size_t v, int port, std::int64_t t) {
        slaves[v].port_time[static_cast<std::size_t>(port)] =
            static_cast<std::uint32_t>(static_cast<std::uint64_t>(t) + clock_offset[v]);
    }
    void process(std::size_t v, std::int64_t t) {
        processed_at[v] = t;
        slaves[v].processing_time = static_cast<std::uint64_t>(t) + clock_offset[v];
    }

    // The frame arrives at v's entry port at true time t; returns when it leaves by it.
    std::int64_t visit(std::size_t v, std::int64_t t) {
        auto& s = slaves[v];
        latch(v, s.entry_port, t);
        if (s.entry_port == 0) process(v, t);
        for (int p = next_port(s.entry_port); p != s.entry_port; p = next_port(p)) {
            const bool open = s.open[static_cast<std::size_t>(p)];
            if (open) {
                if (const auto c = child(v, p)) {
                    t = visit(*c, t + cable[*c]) + cable[*c];
                    latch(v, p, t);
                }
            }
            if (p == 0) process(v, t);  // back at port 0 (or looped there): the processing unit
        }
        return t;
    }

    void run(std::size_t root) {
        processed_at.assign(slaves.size(), 0);
        visit(root, 1'000);
    }
    std::int64_t true_delay(std::size_t v, std::size_t reference) const {
        return processed_at[v] - processed_at[reference];
    }
};

Model model_of(std::vector<LatchedSlave> slaves, std::vector<std::int64_t> cable) {
    Model m;
    m.slaves = std::move(slaves);
    m.cable = std::move(cable);
    // Unrelated clocks, some of them about to wrap at 32 bits.
    for (std::size_t i = 0; i < m.slaves.size(); ++i) {
        m.clock_offset.push_back(0x1'0000'0000ull * (i + 3) - 700 * (i + 1) + (i % 2 ? 0x7FFF'0000ull : 0));
    }
    return m;
}

LatchedSlave slave(std::optional<std::size_t> parent, int parent_port, std::initializer_list<int> open, int entry = 0) {
    LatchedSlave s;
    s.parent = parent;
    s.parent_port = parent_port;
    s.entry_port = entry;
    for (const int p : open) s.open[static_cast<std::size_t>(p)] = true;
    return s;
}

void check_delays(Model& m, std::size_t root, std::size_t reference) {
    m.run(root);
    const auto delays = propagation_delays(m.slaves, reference);
    REQUIRE(delays);
    for (std::size_t i = 0; i < m.slaves.size(); ++i) {
        INFO("slave " << i);
        if (!m.slaves[i].has_dc) {
            CHECK_FALSE((*delays)[i].delay);
            continue;
        }
        REQUIRE((*delays)[i].delay);
        CHECK(*(*delays)[i].delay == m.true_delay(i, reference));
    }
}

}  // namespace

TEST_CASE("a line: each slave's delay is the sum of the cables from the reference", "[dc]") {
    // master -> 0 -> 1 -> 2 -> 3 (port 1 of the last one closed: the frame turns there)
    auto m = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1}), slave(1, 1, {0, 1}), slave(2, 1, {0})},
                      {0, 300, 510, 4120});
    check_delays(m, 0, 0);
    const auto delays = propagation_delays(m.slaves, 0);
    CHECK(*(*delays)[3].delay == 300 + 510 + 4120);
    CHECK(*(*delays)[2].cable == 510);
}

TEST_CASE("a reference clock further down: the slaves before it are reached before it (negative)", "[dc]") {
    auto m = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1}), slave(1, 1, {0, 1}), slave(2, 1, {0})},
                      {0, 250, 250, 250});
    check_delays(m, 0, 2);
    const auto delays = propagation_delays(m.slaves, 2);
    CHECK(*(*delays)[0].delay == -500);
    CHECK(*(*delays)[3].delay == 250);
}

TEST_CASE("an EK1122 junction: the branch on port D is visited before the one on port B", "[dc]") {
    // 0 coupler -> 1 junction; 1 port 3 -> 2 -> 3; 1 port 1 -> 4 -> 5. Positions in processing order.
    auto m = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1, 3}), slave(1, 3, {0, 1}), slave(2, 1, {0}),
                       slave(1, 1, {0, 1}), slave(4, 1, {0})},
                      {0, 200, 900, 300, 1100, 300});
    check_delays(m, 0, 0);
    const auto delays = propagation_delays(m.slaves, 0);
    // Slave 4 is reached after the frame came back from the whole port-D branch.
    const std::int64_t branch_d = 2 * (900 + 300);
    CHECK(*(*delays)[4].delay == 200 + branch_d + 1100);
    CHECK(*(*delays)[3].delay == 200 + 900 + 300);
}

TEST_CASE("a junction with branches on ports C and D and an empty port", "[dc]") {
    // 0 junction (ports 0,1,2,3 open): D -> 1, B -> 2 -> 3, C -> 4
    auto m = model_of(
        {slave({}, 1, {0, 1, 2, 3}), slave(0, 3, {0}), slave(0, 1, {0, 1}), slave(2, 1, {0}), slave(0, 2, {0})},
        {0, 400, 120, 140, 600});
    check_delays(m, 0, 1);
}

TEST_CASE("a line entered from its far end: processed from its first slave on, the same delays", "[dc]") {
    // The RED copy (or a new ACTIVE whose partner is gone) enters the last
    // slave at port 1; slave 0's port 0 has no link, so the frame turns there
    // into its processing unit and is processed 0, 1, 2, 3 on the way back.
    const std::vector<std::int64_t> cable{0, 300, 510, 4120};
    auto forward = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1}), slave(1, 1, {0, 1}), slave(2, 1, {0})}, cable);
    forward.run(0);
    auto far_end =
        model_of({slave(1, 0, {1}, 1), slave(2, 0, {0, 1}, 1), slave(3, 0, {0, 1}, 1), slave({}, 0, {0, 1}, 1)},
                 {300, 510, 4120, 0});
    check_delays(far_end, 3, 0);
    const auto from_front = propagation_delays(forward.slaves, 0);
    const auto from_back = propagation_delays(far_end.slaves, 0);
    REQUIRE(from_front);
    REQUIRE(from_back);
    for (std::size_t i = 0; i < 4; ++i) CHECK(*(*from_back)[i].delay == *(*from_front)[i].delay);
}

TEST_CASE("a slave without DC unit in a line counts as part of the cable", "[dc]") {
    auto m = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1}), slave(1, 1, {0, 1}), slave(2, 1, {0})},
                      {0, 300, 300, 300});
    m.slaves[1].has_dc = false;
    check_delays(m, 0, 0);
    const auto delays = propagation_delays(m.slaves, 0);
    CHECK(*(*delays)[2].cable == 600);
    CHECK((*delays)[1].why == "no DC unit");
}

TEST_CASE("slaves behind a branching slave without DC unit cannot be measured", "[dc]") {
    auto m = model_of({slave({}, 1, {0, 1}), slave(0, 1, {0, 1, 3}), slave(1, 3, {0}), slave(1, 1, {0})},
                      {0, 300, 300, 300});
    m.slaves[1].has_dc = false;
    m.run(0);
    const auto delays = propagation_delays(m.slaves, 0);
    REQUIRE(delays);
    CHECK_FALSE((*delays)[2].delay);
    CHECK_THAT((*delays)[3].why, Catch::Contains("no DC unit and more than one port"));
    CHECK(*(*delays)[0].delay == 0);
}

TEST_CASE("what is not one tree, or a reference without DC unit, is refused", "[dc]") {
    auto two_roots = std::vector<LatchedSlave>{slave({}, 1, {0, 1}), slave({}, 1, {0})};
    CHECK_THAT(propagation_delays(two_roots, 0).error(), Catch::Contains("no parent"));
    auto same_port = std::vector<LatchedSlave>{slave({}, 1, {0, 1}), slave(0, 1, {0}), slave(0, 1, {0})};
    CHECK_THAT(propagation_delays(same_port, 0).error(), Catch::Contains("both hang on port 1"));
    auto closed_port = std::vector<LatchedSlave>{slave({}, 1, {0}), slave(0, 1, {0})};
    CHECK_THAT(propagation_delays(closed_port, 0).error(), Catch::Contains("does not lead on"));
    auto line = std::vector<LatchedSlave>{slave({}, 1, {0, 1}), slave(0, 1, {0})};
    line[0].has_dc = false;
    CHECK_THAT(propagation_delays(line, 0).error(), Catch::Contains("has no DC unit"));
    CHECK_THAT(propagation_delays(line, 5).error(), Catch::Contains("not among"));
}

TEST_CASE("the tree a bus scan's DL status describes, and the ports that lead out of it", "[dc]") {
    using Ports = std::array<bool, kPorts>;
    SECTION("a ring: the last slave's port B leads back to the master's RED side") {
        const auto tree = tree_from_ports({Ports{true, true}, Ports{true, true}, Ports{true, true}});
        REQUIRE(tree);
        CHECK(tree->attachment[1]->parent == 0);
        CHECK(tree->attachment[2]->port == 1);
        REQUIRE(tree->exits.size() == 1);
        CHECK(tree->exits[0].position == 2);
        CHECK(tree->exits[0].port == 1);
    }
    SECTION("a junction: port D's branch first, then B; a line ends where its port B is closed") {
        const auto tree = tree_from_ports({Ports{true, true, false, false}, Ports{true, true, false, true},
                                           Ports{true, true}, Ports{true, false}, Ports{true, false}});
        REQUIRE(tree);
        CHECK(tree->attachment[2]->parent == 1);
        CHECK(tree->attachment[2]->port == 3);
        CHECK(tree->attachment[3]->parent == 2);
        CHECK(tree->attachment[4]->parent == 1);
        CHECK(tree->attachment[4]->port == 1);
        CHECK(tree->exits.empty());
    }
    SECTION("a position with nowhere to hang") {
        const auto tree = tree_from_ports({Ports{true, false}, Ports{true, false}});
        REQUIRE_FALSE(tree);
        CHECK_THAT(tree.error(), Catch::Contains("position 1"));
    }
}

TEST_CASE("orienting a line from its far end: entry ports face the way the frame came", "[dc]") {
    using Ports = std::array<bool, kPorts>;
    const auto tree = tree_from_ports({Ports{true, true}, Ports{true, true}, Ports{true, true}});
    REQUIRE(tree);
    const auto from_master = orient(*tree, 0, 0);
    CHECK_FALSE(from_master[0].parent);
    CHECK(from_master[2].parent == 1u);
    CHECK(from_master[2].entry_port == 0);
    CHECK_FALSE(from_master[2].open[1]);  // the exit is closed while measuring
    const auto from_far_end = orient(*tree, 2, 1);
    CHECK_FALSE(from_far_end[2].parent);
    CHECK(from_far_end[2].entry_port == 1);
    CHECK(from_far_end[1].parent == 2u);
    CHECK(from_far_end[1].parent_port == 0);
    CHECK(from_far_end[1].entry_port == 1);
    CHECK(from_far_end[0].entry_port == 1);
    CHECK_FALSE(from_far_end[0].open[0]);
}

TEST_CASE("measured through orient: a junction tree from the master's side", "[dc]") {
    using Ports = std::array<bool, kPorts>;
    const auto tree = tree_from_ports({Ports{true, true, false, false}, Ports{true, true, false, true},
                                       Ports{true, true}, Ports{true, false}, Ports{true, false}});
    REQUIRE(tree);
    auto m = model_of(orient(*tree, 0, 0), {0, 150, 700, 90, 800});
    check_delays(m, 0, 0);
}
