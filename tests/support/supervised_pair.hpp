#pragma once
// A redundant pair on a simulated segment, its members started together with
// no role (their supervisors decide), as failover tests, the pair benchmark
// and the fault campaign need it:
//
//   m1-main -> slaves -> m2-red, m1-red <-> m2-main   (design.md §1)
//
// It starts ecsim (with its capture) and both ecpaird, waits for the pair to
// settle (one ACTIVE in OP, the other its hot standby), kills, restarts and
// signals members, pulls their cables, and reads back what the slaves
// received. Everything is removed on destruction, also when a test fails.

#include <array>
#include <filesystem>
#include <optional>
#include <string>

#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "segment_capture.hpp"
#include "temp_dir.hpp"

namespace ecpair::test {

struct PairSetup {
    std::filesystem::path eni;
    std::uint32_t cycle_us = 1000;
    std::string redundancy;     // more fields of each member's redundancy { } block
    std::string extra_config;   // more top-level config lines for each member
    std::string demo = "LOOPBACK_CHECK";
    std::string log_level = "debug";
};

bool is_active(const control::StatusReply& s);
bool all_slaves_op(const control::StatusReply& s);
bool hot_standby(const control::StatusReply& s);  // INACTIVE, mirroring a partner in OP

class SupervisedPair {
public:
    explicit SupervisedPair(PairSetup setup, std::string_view prefix = "ecpair-pair");

    EcpairdProcess& member(int i) { return *members_.at(static_cast<std::size_t>(i)); }
    const TestNamespace& ns(int i) const { return i == 0 ? topology_.m1() : topology_.m2(); }
    std::string name(int i) const { return i == 0 ? "m1" : "m2"; }
    RingTopology& topology() { return topology_; }
    EcsimProcess& ecsim() { return *ecsim_; }
    const TempDir& dir() const { return dir_; }

    // Waits (bounded) until one member drives the slaves in OP and the other
    // is its hot standby; the ACTIVE's index. Throws with both logs otherwise.
    int settled(std::chrono::milliseconds timeout = std::chrono::seconds(30));
    // Waits until settled(); the ACTIVE's cycle as its hot standby last
    // mirrored it. At start-up both members may take the bus at once and
    // number cycles alike, or leave numbers out, until the collision is
    // resolved (by design, docs/ARBITRATION.md): a check that every cycle was
    // numbered by exactly one master starts here.
    std::uint64_t settled_cycle();
    // The members ACTIVE now (of those running).
    int active_count();

    // A member stopped and started again (it comes back INACTIVE).
    void restart(int i);
    void kill(int i);  // SIGKILL, and waits for it to be gone
    void pull_cables(int i) const;
    void plug_cables(int i) const;

    // EcsimProcess's counts of slaves leaving OP and SM watchdog expiries
    // since `from` (an offset into ecsim's log).
    std::size_t slaves_leaving_op(std::size_t from) const;
    std::size_t sm_watchdog_expiries(std::size_t from) const;
    // Stops ecsim and reads back its capture.
    SegmentCapture capture();

private:
    void start(int i);

    PairSetup setup_;
    TempDir dir_;
    RingTopology topology_;
    std::optional<EcsimProcess> ecsim_;
    std::array<std::optional<EcpairdProcess>, 2> members_;
};

}  // namespace ecpair::test
