// SlaveMonitor against a bus that answers each station's AL status read:
// a round reads every slave in one exchange_all (one wake-up of the monitor
// however many slaves), fills the slave state image and raises the events.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sequencer/slave_monitor.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "fakes.hpp"

namespace ecpair::test {
namespace {

std::shared_ptr<const eni::EniConfig> four_slaves() {
    auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/advantech_io_ring_4slaves.xml"));
    REQUIRE(loaded);
    REQUIRE((*loaded)->slaves.size() == 4);
    return *loaded;
}

// Counts the batches it is given and answers every request through `handler`.
class BatchCountingBus final : public bus::BusAccess {
public:
    explicit BatchCountingBus(ScriptedBus::Handler handler) : handler_(std::move(handler)) {}
    BusReply exchange(const bus::DatagramRequest& request) override {
        ++single_exchanges;
        return handler_(request);
    }
    std::vector<BusReply> exchange_all(std::span<const bus::DatagramRequest> requests) override {
        batch_sizes.push_back(requests.size());
        std::vector<BusReply> replies;
        for (const auto& request : requests) replies.push_back(handler_(request));
        return replies;
    }
    int single_exchanges = 0;
    std::vector<std::size_t> batch_sizes;

private:
    ScriptedBus::Handler handler_;
};

std::vector<master::Event> drain(master::EventQueue& events) {
    std::vector<master::Event> out;
    for (const auto& report : events.pop_all(std::chrono::milliseconds(0))) out.push_back(report.event);
    return out;
}

}  // namespace

TEST_CASE("a monitor round reads every slave's AL status in one batch", "[sequencer][monitor]") {
    const auto eni = four_slaves();
    const auto second = eni->slaves[1].info.phys_addr;
    const auto third = eni->slaves[2].info.phys_addr;
    BatchCountingBus bus([&](const bus::DatagramRequest& r) -> BusReply {
        CHECK(r.command == wire::Command::Fprd);
        CHECK(ado_of(r) == wire::reg::kAlStatus);
        CHECK(r.data.size() == 6);
        if (adp_of(r) == second) return reply({0, 0, 0, 0, 0, 0}, 0);           // not there
        if (adp_of(r) == third) return reply({0x14, 0, 0, 0, 0x1B, 0}, 1);      // SAFEOP + error 0x001B
        return reply({0x08, 0, 0, 0, 0, 0}, 1);                                 // OP
    });
    master::SlaveStateImage image(eni->slaves.size());
    master::EventQueue events;
    sequencer::SlaveMonitor monitor(eni, bus, image, &events, [] { return true; }, std::chrono::hours(1));

    monitor.poll_once();

    CHECK(bus.batch_sizes == std::vector<std::size_t>{4});
    CHECK(bus.single_exchanges == 0);
    const auto entries = image.snapshot();
    CHECK(entries[0].present);
    CHECK(entries[0].al_status == 0x08);
    CHECK_FALSE(entries[1].present);
    CHECK(entries[2].present);
    CHECK(entries[2].al_status == 0x14);
    CHECK(entries[2].al_status_code == 0x001B);
    CHECK(entries[3].station_address == eni->slaves[3].info.phys_addr);

    const auto raised = drain(events);
    int presence = 0, errors = 0;
    for (const auto& e : raised) {
        if (e.kind == master::events::kSlavePresence) ++presence;
        if (e.kind == master::events::kSlaveStateError) {
            ++errors;
            CHECK(e.a == 2);
            CHECK(e.c == 0x001B);
        }
    }
    CHECK(presence == 3);  // three slaves went from unknown to present; the absent one did not change
    CHECK(errors == 1);

    monitor.poll_once();  // nothing changed: no new events
    CHECK(bus.batch_sizes == std::vector<std::size_t>{4, 4});
    CHECK(drain(events).empty());
}

TEST_CASE("a monitor round on an INACTIVE master leaves the image alone", "[sequencer][monitor]") {
    const auto eni = four_slaves();
    BatchCountingBus bus([](const bus::DatagramRequest&) { return bus_error(bus::BusErrc::MasterRedStateInactive); });
    master::SlaveStateImage image(eni->slaves.size());
    master::EventQueue events;
    sequencer::SlaveMonitor monitor(eni, bus, image, &events, [] { return true; }, std::chrono::hours(1));
    monitor.poll_once();
    CHECK(image.snapshot() == std::vector<master::SlaveStateEntry>(eni->slaves.size()));
    CHECK(drain(events).empty());
    CHECK(monitor.rounds() == 0);
}

}  // namespace ecpair::test
