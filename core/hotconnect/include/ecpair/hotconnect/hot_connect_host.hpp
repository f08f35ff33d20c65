#pragma once
// What Hot-Connect needs of the cyclic master: the bus (through the cycle's
// acyclic queue), the slave state image, the state the cyclic frames run
// in, the expected WKCs and the topology watch. MasterHost is the real one;
// tests give their own over a simulated segment.

#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/master/slave_state_image.hpp"
#include "ecpair/master/topology_watch.hpp"

namespace ecpair::hotconnect {

class HotConnectHost {
public:
    virtual ~HotConnectHost() = default;
    virtual bus::BusAccess& bus() = 0;
    virtual master::SlaveStateImage& slaves() = 0;
    virtual eni::SlaveState cyclic_state() const = 0;
    virtual std::uint64_t cycle() const = 0;
    virtual const master::CyclicPlan& plan() const = 0;
    virtual void set_expected_wkcs(std::vector<std::optional<std::uint16_t>> expected) = 0;
    virtual master::TopologyWatch* topology_watch() = 0;  // null: no cycle to watch
    // WKC deviations the cycle put down to topology changes so far.
    virtual std::uint64_t wkc_topology_deviations() const = 0;
};

class MasterHost final : public HotConnectHost {
public:
    explicit MasterHost(master::Master& master) : master_(master) {}
    bus::BusAccess& bus() override { return master_.bus(); }
    master::SlaveStateImage& slaves() override { return master_.slaves(); }
    eni::SlaveState cyclic_state() const override { return master_.state(); }
    std::uint64_t cycle() const override { return master_.cycle(); }
    const master::CyclicPlan& plan() const override { return master_.plan(); }
    void set_expected_wkcs(std::vector<std::optional<std::uint16_t>> expected) override {
        master_.set_expected_wkcs(std::move(expected));
    }
    master::TopologyWatch* topology_watch() override { return &master_.topology_watch(); }
    std::uint64_t wkc_topology_deviations() const override { return master_.stats().wkc_topology_deviations; }

private:
    master::Master& master_;
};

}  // namespace ecpair::hotconnect
