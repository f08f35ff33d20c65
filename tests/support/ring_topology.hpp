#pragma once
// design.md §1 on one machine: the slave chain (ecsim) in one namespace and
// each controller in its own, veth pairs as cables.
//
//   single master:   m1-main (m1) <-> sim-main (sim),  m1-red (m1) <-> sim-red (sim)
//   pair:            m1-main (m1) <-> sim-main (sim),  m1-red (m1) <-> m2-main (m2),
//                    m2-red (m2) <-> sim-red (sim)
//
// Pulling a cable is `ip link set <end> down`: both ends lose carrier.

#include <memory>
#include <string>

#include "netns.hpp"

namespace ecpair::test {

enum class Controllers { Single, Pair };

enum class Cable {
    M1Main,        // m1-main <-> sim-main
    RingReturn,    // sim-red <-> m1-red (single) or m2-red (pair)
    MasterMaster,  // m1-red <-> m2-main (pair only)
};

class RingTopology {
public:
    explicit RingTopology(Controllers controllers);

    const TestNamespace& sim() const { return *sim_; }
    const TestNamespace& m1() const { return *m1_; }
    const TestNamespace& m2() const { return *m2_; }  // pair only
    Controllers controllers() const { return controllers_; }

    void pull(Cable cable) const { set(cable, false); }
    void plug(Cable cable) const { set(cable, true); }
    // Frames the cables swallowed: sent by either end while the other end was down.
    std::uint64_t frames_dropped_in_cables() const;

private:
    void set(Cable cable, bool up) const;

    Controllers controllers_;
    std::unique_ptr<TestNamespace> sim_;
    std::unique_ptr<TestNamespace> m1_;
    std::unique_ptr<TestNamespace> m2_;
};

}  // namespace ecpair::test
