#pragma once
// A simulated segment built from an ENI, reached through SegmentBusAccess,
// and a stand-in for the cyclic master that applies state requests at once
// and remembers them.

#include <catch2/catch.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include <fmt/format.h>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/sim/segment_bus_access.hpp"

namespace ecpair::test {

// A modifiable copy of a real ENI from tests/data/eni (or a path under tests/data).
inline std::shared_ptr<eni::EniConfig> load_eni_copy(const std::string& name) {
    const auto path = name.find('/') == std::string::npos ? fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, name)
                                                          : fmt::format("{}/{}", ECPAIR_TEST_DATA_DIR, name);
    auto loaded = eni::load_eni_file(path);
    REQUIRE(loaded);
    return std::make_shared<eni::EniConfig>(**loaded);
}

// The same ENI with every CoE InitCmd removed (for as long as the simulated
// slaves have no CoE server, this is what reaches OP).
inline std::shared_ptr<eni::EniConfig> without_coe_init_cmds(std::shared_ptr<eni::EniConfig> eni) {
    for (auto& slave : eni->slaves) {
        if (slave.mailbox) slave.mailbox->coe_init_cmds.clear();
    }
    return eni;
}

class SimulatedBus {
public:
    // The segment holds the slaves `wiring` describes (often the configured ENI itself).
    explicit SimulatedBus(const eni::EniConfig& wiring) : segment(build(wiring)), bus(segment) {}

    sim::Segment segment;
    sim::SegmentBusAccess bus;

private:
    static sim::Segment build(const eni::EniConfig& wiring) {
        auto segment = sim::Segment::from_eni(wiring);
        REQUIRE(segment);
        return std::move(segment).value();
    }
};

class FakeCyclicMaster {
public:
    sequencer::StateMachineHooks hooks() {
        sequencer::StateMachineHooks h;
        h.request_cyclic_state = [this](eni::SlaveState s) {
            std::lock_guard lock(mutex_);
            applied_.push_back(s);
            state_ = s;
        };
        h.cyclic_state = [this] { return state_.load(); };
        return h;
    }
    std::vector<eni::SlaveState> applied() const {
        std::lock_guard lock(mutex_);
        return applied_;
    }

private:
    mutable std::mutex mutex_;
    std::vector<eni::SlaveState> applied_;
    std::atomic<eni::SlaveState> state_{eni::SlaveState::Init};
};

// Requests `target` and waits for the sequence to end; the error, if any.
inline std::optional<sequencer::SequenceError> run_to(sequencer::MasterStateMachine& machine,
                                                      sequencer::MasterState target) {
    machine.request(target);
    REQUIRE(machine.wait_idle(std::chrono::seconds(120)));
    return machine.last_error();
}

}  // namespace ecpair::test
