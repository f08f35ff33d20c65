#pragma once
// A master without a cycle for the Hot-Connect tests: the simulated segment
// of a generated ENI reached through SegmentBusAccess, the master state
// machine on it, and HotConnect with a host that records the expected WKCs
// it is given. Faults go to the segment between two frames (with_segment).

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "ecpair/eni/loader.hpp"
#include "ecpair/hotconnect/hot_connect.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/hotconnect/hot_connect_events.hpp"
#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/master/slave_state_image.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/sim/segment_bus_access.hpp"

namespace ecpair::test {

class RecordingHost final : public hotconnect::HotConnectHost {
public:
    RecordingHost(bus::BusAccess& bus, master::SlaveStateImage& slaves, master::CyclicPlan plan)
        : bus_(bus), slaves_(slaves), plan_(std::move(plan)) {}

    bus::BusAccess& bus() override { return bus_; }
    master::SlaveStateImage& slaves() override { return slaves_; }
    eni::SlaveState cyclic_state() const override { return state.load(); }
    std::uint64_t cycle() const override { return 0; }
    const master::CyclicPlan& plan() const override { return plan_; }
    void set_expected_wkcs(std::vector<std::optional<std::uint16_t>> expected) override {
        std::lock_guard lock(mutex_);
        expected_ = std::move(expected);
    }
    master::TopologyWatch* topology_watch() override { return nullptr; }
    std::uint64_t wkc_topology_deviations() const override { return 0; }

    std::vector<std::optional<std::uint16_t>> expected() const {
        std::lock_guard lock(mutex_);
        return expected_;
    }
    std::atomic<eni::SlaveState> state{eni::SlaveState::Init};

private:
    bus::BusAccess& bus_;
    master::SlaveStateImage& slaves_;
    master::CyclicPlan plan_;
    mutable std::mutex mutex_;
    std::vector<std::optional<std::uint16_t>> expected_;
};

inline sim::GeneratedEniOptions grouped(std::uint32_t groups = 2, std::uint32_t group_slaves = 2) {
    sim::GeneratedEniOptions o;
    o.slaves = 3;
    o.groups = groups;
    o.group_slaves = group_slaves;
    o.input_bytes = 4;
    o.output_bytes = 4;
    return o;
}

class HotConnectBench {
public:
    explicit HotConnectBench(const sim::GeneratedEniOptions& options, hotconnect::HotConnectOptions hc = fast())
        : eni_(load(options)),
          segment_(build(*eni_)),
          bus(segment_),
          image(eni_->slaves.size()),
          host(bus, image, plan_of(*eni_)),
          hc_options_(hc) {
        // A single master: the line's end turns frames back (junction port C is reached too).
        segment_.set_side_link(sim::Side::Red, false);
    }
    ~HotConnectBench() {
        hot_connect.reset();
        machine.reset();
    }

    static hotconnect::HotConnectOptions fast() {
        hotconnect::HotConnectOptions o;
        o.poll_period = std::chrono::milliseconds(10);
        o.settle_gap = std::chrono::milliseconds(1);
        o.detection_timeout = std::chrono::milliseconds(2000);
        return o;
    }

    const eni::EniConfig& eni() const { return *eni_; }

    // Starts the state machine and Hot-Connect; the slaves reach `target`.
    void start(sequencer::MasterState target = sequencer::MasterState::Op) {
        hot_connect = std::make_unique<hotconnect::HotConnect>(eni_, host, &events, hc_options_);
        sequencer::StateMachineHooks hooks;
        hooks.request_cyclic_state = [this](eni::SlaveState s) { host.state = s; };
        hooks.cyclic_state = [this] { return host.state.load(); };
        hooks.on_scan = [this](const sequencer::ScanOutcome& outcome) { hot_connect->on_startup_scan(outcome); };
        hooks.on_done = [this](const sequencer::SequenceResult& result) {
            hot_connect->on_sequence_idle(result.reached, !result.error && result.reached == result.target);
        };
        machine = std::make_unique<sequencer::MasterStateMachine>(eni_, bus, std::move(hooks), &events);
        hot_connect->set_presence_listener([this](const std::vector<bool>& present, const std::vector<std::uint16_t>& shift) {
            machine->update_presence(present, shift);
        });
        machine->request(target);
        REQUIRE(machine->wait_idle(std::chrono::seconds(30)));
        INFO((machine->last_error() ? machine->last_error()->message : std::string()));
        REQUIRE_FALSE(machine->last_error());
        REQUIRE(hot_connect->wait_idle(std::chrono::seconds(10)));
    }

    void with_segment(const std::function<void(sim::Segment&)>& f) { bus.with_segment(f); }

    std::uint8_t al_state(std::size_t position) {
        std::uint8_t state = 0;
        with_segment([&](sim::Segment& s) { state = s.slave(position).al_status(); });
        return state;
    }

    // Collects events until `done` holds for one of them, or the timeout.
    std::optional<master::Event> wait_event(const std::function<bool(const master::Event&)>& done,
                                            std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < deadline) {
            for (const auto& report : events.pop_all(std::chrono::milliseconds(20))) {
                const master::Event& e = report.event;
                seen.push_back(e);
                if (done(e)) return e;
            }
        }
        return std::nullopt;
    }
    std::optional<master::Event> wait_event(master::EventKind kind, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
        return wait_event([kind](const master::Event& e) { return e.kind == kind; }, timeout);
    }
    bool saw(master::EventKind kind, std::optional<std::uint32_t> a = std::nullopt) const {
        for (const auto& e : seen) {
            if (e.kind == kind && (!a || e.a == *a)) return true;
        }
        return false;
    }
    std::string seen_text() const {
        std::string text;
        for (const auto& e : seen) text += master::EventDescriber(eni_, nullptr).describe(e) + "\n";
        return text;
    }

    // The expected WKC of the first datagram with this command (flat order).
    std::optional<std::uint16_t> expected_of(wire::Command command) const {
        const auto expected = host.expected();
        std::size_t flat = 0;
        for (const auto& frame : host.plan().frames) {
            for (const auto& d : frame.datagrams) {
                if (d.command == command) return flat < expected.size() ? expected[flat] : std::nullopt;
                ++flat;
            }
        }
        return std::nullopt;
    }

    // The slave's position in the segment (1-based) by its station address as configured.
    std::size_t position_of(std::uint16_t phys) const {
        for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
            if (eni_->slaves[i].info.phys_addr == phys) return i + 1;
        }
        FAIL("no slave " << phys);
        return 0;
    }

private:
    static std::shared_ptr<const eni::EniConfig> load(const sim::GeneratedEniOptions& options) {
        auto eni = eni::load_eni_string(sim::generate_eni(options), "generated.xml");
        REQUIRE(eni);
        return *eni;
    }
    static sim::Segment build(const eni::EniConfig& eni) {
        auto segment = sim::Segment::from_eni(eni);
        REQUIRE(segment);
        return std::move(segment).value();
    }
    static master::CyclicPlan plan_of(const eni::EniConfig& eni) {
        auto plan = master::CyclicPlan::build(eni, {});
        REQUIRE(plan);
        return std::move(plan).value();
    }

    std::shared_ptr<const eni::EniConfig> eni_;
    sim::Segment segment_;

public:
    sim::SegmentBusAccess bus;
    master::SlaveStateImage image;
    master::EventQueue events{8192};
    RecordingHost host;
    std::unique_ptr<sequencer::MasterStateMachine> machine;
    std::unique_ptr<hotconnect::HotConnect> hot_connect;
    std::vector<master::Event> seen;

private:
    hotconnect::HotConnectOptions hc_options_;
};

}  // namespace ecpair::test
