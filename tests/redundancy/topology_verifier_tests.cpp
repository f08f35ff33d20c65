// After a hot takeover the new ACTIVE checks the mirrored topology with a
// real scan in the background. Right after a takeover the ring may still be
// open (the failed partner's side closing its ports), so a scan without an
// answer is retried; these run the verifier against a simulated segment
// behind a bus that stays silent for a while.

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <memory>

#include "ecpair/redundancy/redundancy_events.hpp"
#include "ecpair/redundancy/topology_verifier.hpp"
#include "segment_fixture.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

// Answers nothing for the first `silent` exchanges (the ring still open), then passes them on.
class SilentAtFirst final : public bus::BusAccess {
public:
    SilentAtFirst(bus::BusAccess& bus, int silent) : bus_(bus), silent_(silent) {}
    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override {
        if (silent_.fetch_sub(1) > 0) return unexpected(bus::BusError{bus::BusErrc::Timeout, "no reply (test)"});
        return bus_.exchange(request);
    }

private:
    bus::BusAccess& bus_;
    std::atomic<int> silent_;
};

std::vector<master::SlaveStateEntry> all_present(const eni::EniConfig& eni) {
    std::vector<master::SlaveStateEntry> entries(eni.slaves.size());
    for (auto& e : entries) e.present = true;
    return entries;
}

// The TopologyVerified events within `timeout`.
std::vector<master::Event> verified_events(master::EventQueue& events, std::chrono::milliseconds timeout) {
    std::vector<master::Event> out;
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (out.empty() && std::chrono::steady_clock::now() < until) {
        for (const auto& report : events.pop_all(50ms)) {
            if (report.event.kind == redundancy::events::kTopologyVerified) out.push_back(report.event);
        }
    }
    return out;
}

}  // namespace

TEST_CASE("a background scan that gets no answer at first is retried until the ring answers", "[redundancy][verifier]") {
    const auto eni = test::load_eni_copy("twincat_kpierczy_5slaves.xml");
    test::SimulatedBus simulated(*eni);
    SilentAtFirst bus(simulated.bus, 3);  // the first attempts fail on their first datagram
    master::EventQueue events;
    redundancy::TopologyVerifier verifier(eni, bus, events, 1ms);
    verifier.verify(all_present(*eni));
    const auto verified = verified_events(events, 10s);
    REQUIRE(verified.size() == 1);
    CHECK(verified[0].a == 1);  // confirmed
    CHECK(verified[0].b == eni->slaves.size());
}

TEST_CASE("a bus that never answers leaves the topology unverified after the last attempt, without an event",
          "[redundancy][verifier]") {
    const auto eni = test::load_eni_copy("twincat_kpierczy_5slaves.xml");
    test::SimulatedBus simulated(*eni);
    SilentAtFirst bus(simulated.bus, 1'000'000);
    master::EventQueue events;
    {
        redundancy::TopologyVerifier verifier(eni, bus, events, 1ms);
        verifier.verify(all_present(*eni));
    }  // the destructor waits for the attempts to end
    CHECK(verified_events(events, 100ms).empty());
}

TEST_CASE("a slave missing from the bus contradicts the mirrored image", "[redundancy][verifier]") {
    const auto eni = test::load_eni_copy("twincat_kpierczy_5slaves.xml");
    auto wiring = *eni;
    wiring.slaves.pop_back();  // the last slave is not on the bus
    test::SimulatedBus simulated(wiring);
    master::EventQueue events;
    redundancy::TopologyVerifier verifier(eni, simulated.bus, events, 1ms);
    verifier.verify(all_present(*eni));
    const auto verified = verified_events(events, 10s);
    REQUIRE(verified.size() == 1);
    CHECK(verified[0].a == 0);
    CHECK(verified[0].b == eni->slaves.size() - 1);
}
