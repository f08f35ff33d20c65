// The mailbox service against the fake mailbox slave (virtual time): a
// request's typed result through a future and a completion; every refusal at
// submit with its own code and a message naming the slave; a request cut by
// the role change, in flight and still queued, as Interrupted (retryable);
// each slave's order kept; a full queue; shutting down; an emergency during
// a transfer as an event; the SII write guard. The poll of idle mailboxes
// runs against the simulated segment (real time, bounded wait).

#include <catch2/catch.hpp>

#include <atomic>
#include <condition_variable>
#include <mutex>

#include "ecpair/master/event_describer.hpp"
#include "ecpair/sequencer/mailbox_service.hpp"
#include "fake_mailbox_slave.hpp"
#include "fakes.hpp"
#include "segment_fixture.hpp"

namespace ecpair::test {
namespace {

using sequencer::MailboxService;
using sequencer::ServiceErrc;

// One slave with a CoE mailbox where FakeMailboxSlave has it, and one without a mailbox.
std::shared_ptr<const eni::EniConfig> two_slaves() {
    auto eni = std::make_shared<eni::EniConfig>();
    eni::Slave drive;
    drive.info.name = "Drive";
    drive.info.phys_addr = FakeMailboxSlave::kStation;
    eni::Mailbox mailbox;
    mailbox.send = eni::MailboxArea{0x1000, FakeMailboxSlave::kMailboxLength};
    mailbox.recv = eni::MailboxArea{0x1080, FakeMailboxSlave::kMailboxLength};
    mailbox.protocols = eni::kCoE;
    drive.mailbox = mailbox;
    eni->slaves.push_back(drive);
    eni::Slave coupler;
    coupler.info.name = "Coupler";
    coupler.info.phys_addr = 1002;
    eni->slaves.push_back(coupler);
    return eni;
}

// The fake slave behind a bus that can refuse like an INACTIVE master's
// queue, refuse from the Nth exchange on (a role change mid-transfer), and
// hold exchanges until released.
class RoleBus final : public bus::BusAccess {
public:
    explicit RoleBus(bus::BusAccess& slave) : slave_(slave) {}

    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override {
        {
            std::unique_lock lock(mutex_);
            held_cv_.wait(lock, [this] { return !hold_; });
            if (refuse_after_ && exchanges_ >= *refuse_after_) refusal_ = bus::BusErrc::MasterRedStateInactive;
            ++exchanges_;
            if (refusal_) return unexpected(bus::BusError{*refusal_, std::string(bus::to_string(*refusal_))});
        }
        return slave_.exchange(request);
    }
    std::optional<bus::BusErrc> refusal() const override {
        std::lock_guard lock(mutex_);
        return refusal_;
    }
    void refuse(std::optional<bus::BusErrc> reason) {
        std::lock_guard lock(mutex_);
        refusal_ = reason;
    }
    void refuse_after(std::size_t exchanges) {
        std::lock_guard lock(mutex_);
        refuse_after_ = exchanges_ + exchanges;
    }
    void hold(bool on) {
        {
            std::lock_guard lock(mutex_);
            hold_ = on;
        }
        held_cv_.notify_all();
    }

private:
    bus::BusAccess& slave_;
    mutable std::mutex mutex_;
    std::condition_variable held_cv_;
    std::optional<bus::BusErrc> refusal_;
    std::optional<std::size_t> refuse_after_;
    std::size_t exchanges_ = 0;
    bool hold_ = false;
};

struct ServiceFixture {
    std::shared_ptr<const eni::EniConfig> eni = two_slaves();
    FakeMailboxSlave slave;
    RoleBus bus{slave};
    VirtualClock clock;
    sequencer::SlaveMailboxes mailboxes{*eni, bus, clock};
    master::EventQueue events;
    std::atomic<bool> coupler_present{true};

    std::unique_ptr<MailboxService> make(sequencer::MailboxServiceOptions options = {}) {
        options.emergency_poll = std::chrono::milliseconds(0);
        sequencer::MailboxServiceHooks hooks;
        hooks.events = &events;
        hooks.present = [this](std::size_t i) { return i == 0 || coupler_present.load(); };
        return std::make_unique<MailboxService>(eni, bus, mailboxes, hooks, clock, options);
    }
};

TEST_CASE_METHOD(ServiceFixture, "An SDO upload and download through the service: typed results, future and completion",
                 "[sequencer][mailbox-service]") {
    auto service = make();
    slave.objects[{0x6060, 0}] = {0x08};
    const auto value = service->sdo_upload(sequencer::SdoUpload{0, 0x6060, 0}).get();
    REQUIRE(value);
    CHECK(*value == std::vector<std::uint8_t>{0x08});

    std::promise<sequencer::ServiceResult<void>> written;
    service->sdo_download(sequencer::SdoDownload{0, 0x6060, 0, {0x0A}},
                          [&written](sequencer::ServiceResult<void> r) { written.set_value(std::move(r)); });
    REQUIRE(written.get_future().get());
    CHECK(slave.objects[{0x6060, 0}] == std::vector<std::uint8_t>{0x0A});
    CHECK(service->pending() == 0);
}

TEST_CASE_METHOD(ServiceFixture, "An SDO abort names the slave, the object and the abort code's text",
                 "[sequencer][mailbox-service]") {
    auto service = make();
    const auto result = service->sdo_upload(sequencer::SdoUpload{0, 0x7000, 1}).get();
    REQUIRE_FALSE(result);
    CHECK(result.error().code == ServiceErrc::SdoAbort);
    CHECK(result.error().abort_code == wire::sdo_abort::kObjectDoesNotExist);
    CHECK(result.error().position == 0);
    CHECK_FALSE(result.error().retryable());
    CHECK(result.error().message ==
          "SdoAbort: slave 0 'Drive' (station 1001): SDO 0x7000:01 upload: aborted: 0x06020000 object does not exist "
          "in the object dictionary");
}

TEST_CASE_METHOD(ServiceFixture, "At the INACTIVE every request is refused at once, on the caller's thread",
                 "[sequencer][mailbox-service]") {
    auto service = make();
    bus.refuse(bus::BusErrc::MasterRedStateInactive);
    std::optional<sequencer::ServiceResult<std::vector<std::uint8_t>>> result;
    service->sdo_upload(sequencer::SdoUpload{0, 0x6060, 0},
                        [&result](sequencer::ServiceResult<std::vector<std::uint8_t>> r) { result = std::move(r); });
    REQUIRE(result);  // completed before sdo_upload returned
    REQUIRE_FALSE(*result);
    CHECK(result->error().code == ServiceErrc::MasterRedStateInactive);
    CHECK_FALSE(result->error().retryable());
    CHECK(result->error().message ==
          "MasterRedStateInactive: slave 0 'Drive' (station 1001): SDO 0x6060:00 upload: this member is INACTIVE and "
          "must not talk to the slaves: ask the ACTIVE");
    // Every kind is refused alike, and nothing reached the bus.
    CHECK(service->register_read(sequencer::RegisterRead{1, 0x0130, 2}).get().error().code ==
          ServiceErrc::MasterRedStateInactive);
    CHECK(service->sii_read(sequencer::SiiRead{1}).get().error().code == ServiceErrc::MasterRedStateInactive);
    CHECK(slave.requests.empty());
}

TEST_CASE_METHOD(ServiceFixture, "A transfer cut by the role change fails Interrupted, retryable, so does one still queued",
                 "[sequencer][mailbox-service]") {
    sequencer::MailboxServiceOptions options;
    options.workers = 1;
    auto service = make(options);
    slave.objects[{0x2000, 0}] = std::vector<std::uint8_t>(300, 0x11);
    bus.hold(true);
    auto first = service->sdo_upload(sequencer::SdoUpload{0, 0x2000, 0});
    auto second = service->sdo_upload(sequencer::SdoUpload{0, 0x2000, 0});
    bus.refuse_after(3);  // the first transfer gets three datagrams through, then the member is INACTIVE
    bus.hold(false);
    const auto cut = first.get();
    REQUIRE_FALSE(cut);
    CHECK(cut.error().code == ServiceErrc::Interrupted);
    CHECK(cut.error().retryable());
    CHECK_THAT(cut.error().message, Catch::StartsWith("Interrupted: slave 0 'Drive' (station 1001): SDO 0x2000:00 upload") &&
                                        Catch::EndsWith("send it again to the new ACTIVE"));
    const auto queued = second.get();
    REQUIRE_FALSE(queued);
    CHECK(queued.error().code == ServiceErrc::Interrupted);
    CHECK_THAT(queued.error().message, Catch::Contains("still queued"));
}

TEST_CASE_METHOD(ServiceFixture, "Refusals at submit: position, presence, protocol, parameters",
                 "[sequencer][mailbox-service]") {
    auto service = make();
    const auto code = [](const auto& result) { return result ? std::optional<ServiceErrc>() : result.error().code; };
    const auto beyond = service->sdo_upload(sequencer::SdoUpload{5, 0x1000, 0}).get();
    CHECK(code(beyond) == ServiceErrc::InvalidParam);
    CHECK_THAT(beyond.error().message, Catch::Contains("no slave at position 5: the ENI configures 2 (positions 0..1)"));
    coupler_present = false;
    CHECK(code(service->register_read(sequencer::RegisterRead{1, 0x0130, 2}).get()) == ServiceErrc::SlaveNotPresent);
    coupler_present = true;
    const auto no_mailbox = service->sdo_upload(sequencer::SdoUpload{1, 0x1000, 0}).get();
    CHECK(code(no_mailbox) == ServiceErrc::NotSupported);
    CHECK_THAT(no_mailbox.error().message, Catch::EndsWith("the slave has no mailbox"));
    const auto no_foe = service->foe_read(sequencer::FoeRead{0, "fw"}).get();
    CHECK(code(no_foe) == ServiceErrc::NotSupported);
    CHECK_THAT(no_foe.error().message, Catch::EndsWith("the ENI does not give the slave this mailbox protocol"));
    CHECK(code(service->foe_write(sequencer::FoeWrite{0, ""}).get()) == ServiceErrc::InvalidParam);
    CHECK(code(service->sdo_download(sequencer::SdoDownload{0, 0x6060, 0, {}}).get()) == ServiceErrc::InvalidParam);
    CHECK(code(service->register_read(sequencer::RegisterRead{1, 0xFFFF, 2}).get()) == ServiceErrc::InvalidParam);
    CHECK(code(service->register_write(sequencer::RegisterWrite{1, 0x0120, {}}).get()) == ServiceErrc::InvalidParam);
    // A register the fake slave does not answer: WKC 0.
    const auto silent = service->register_read(sequencer::RegisterRead{1, 0x0130, 2}).get();
    CHECK(code(silent) == ServiceErrc::NoResponse);
    CHECK_THAT(silent.error().message, Catch::EndsWith("register read of 2 byte(s) at 0x0130: WKC 0 (no answer)"));
}

TEST_CASE_METHOD(ServiceFixture, "Each slave's requests run in the order they came, a full queue answers Busy",
                 "[sequencer][mailbox-service]") {
    sequencer::MailboxServiceOptions options;
    options.max_queued = 5;
    auto service = make(options);
    slave.objects[{0x6060, 0}] = {0};
    bus.hold(true);
    std::vector<std::future<sequencer::ServiceResult<void>>> writes;
    for (std::uint8_t v = 1; v <= 5; ++v) writes.push_back(service->sdo_download(sequencer::SdoDownload{0, 0x6060, 0, {v}}));
    const auto busy = service->sdo_download(sequencer::SdoDownload{0, 0x6060, 0, {9}}).get();
    REQUIRE_FALSE(busy);
    CHECK(busy.error().code == ServiceErrc::Busy);
    bus.hold(false);
    for (auto& w : writes) REQUIRE(w.get());
    REQUIRE(slave.requests.size() == 5);
    for (std::size_t i = 0; i < 5; ++i) CHECK(slave.requests[i].data == std::vector<std::uint8_t>{std::uint8_t(i + 1)});
    CHECK(slave.objects[{0x6060, 0}] == std::vector<std::uint8_t>{5});
}

TEST_CASE_METHOD(ServiceFixture, "Shutting down fails what is still queued with Cancelled", "[sequencer][mailbox-service]") {
    sequencer::MailboxServiceOptions options;
    options.workers = 1;
    auto service = make(options);
    slave.objects[{0x6060, 0}] = {0};
    bus.hold(true);
    auto running = service->sdo_upload(sequencer::SdoUpload{0, 0x6060, 0});
    auto waiting = service->sdo_upload(sequencer::SdoUpload{0, 0x6060, 0});
    std::thread release([this] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        bus.hold(false);
    });
    service.reset();
    release.join();
    const auto cancelled = waiting.get();
    REQUIRE_FALSE(cancelled);
    CHECK(cancelled.error().code == ServiceErrc::Cancelled);
    (void)running.get();  // ended, one way or the other
}

TEST_CASE_METHOD(ServiceFixture, "An emergency during a transfer becomes a coe-emergency event", "[sequencer][mailbox-service]") {
    auto service = make();
    slave.objects[{0x6060, 0}] = {0};
    slave.emergency_first = true;
    REQUIRE(service->sdo_download(sequencer::SdoDownload{0, 0x6060, 0, {1}}).get());
    const auto seen = events.pop_all(std::chrono::milliseconds(0));
    REQUIRE(seen.size() == 1);
    CHECK(seen[0].event.kind == master::events::kCoeEmergency);
    const auto e = sequencer::CoeEmergencyEvent::from(seen[0].event);
    CHECK(e.slave == 0);
    CHECK(e.emergency.error_code == 0x8110);
    CHECK(master::EventDescriber(nullptr, nullptr).describe(seen[0]) ==
          "cycle 0: slave #1 (not in the ENI): CoE emergency 0x8110 (communication), error register 0x00, data 00 00 00 00 00");
}

TEST_CASE_METHOD(ServiceFixture, "SII writes are guarded", "[sequencer][mailbox-service]") {
    auto locked = make();
    const auto refused = locked->sii_write(sequencer::SiiWrite{1, 0x10, {1, 2}}).get();
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == ServiceErrc::InvalidState);
    locked.reset();

    sequencer::MailboxServiceOptions options;
    options.allow_sii_write = true;
    auto service = make(options);
    CHECK(service->sii_write(sequencer::SiiWrite{1, 0x10, {1, 2, 3}}).get().error().code == ServiceErrc::InvalidParam);
    const auto partial = service->sii_write(sequencer::SiiWrite{1, 4, {1, 0}}).get();
    REQUIRE_FALSE(partial);
    CHECK_THAT(partial.error().message, Catch::Contains("must cover all eight"));
    std::vector<std::uint8_t> head(16, 0);
    head[14] = 0x00;  // not the checksum of seven zero words
    const auto bad_crc = service->sii_write(sequencer::SiiWrite{1, 0, head}).get();
    REQUIRE_FALSE(bad_crc);
    CHECK_THAT(bad_crc.error().message, Catch::Contains("the checksum in word 7 is 0x00, the words 0-6 give 0x"));
}

TEST_CASE("The poll of idle mailboxes finds an emergency the slave sent on its own", "[sequencer][mailbox-service][segment]") {
    const std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/soe_eoe_drive_2slaves.xml");
    SimulatedBus sim(*eni);
    VirtualClock clock;
    sequencer::SlaveMailboxes mailboxes(*eni, sim.bus, clock);
    {
        sequencer::StateMachineOptions sm;
        sm.mailboxes = &mailboxes;
        sequencer::MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock, sm);
        REQUIRE_FALSE(run_to(machine, sequencer::MasterState::Preop));
    }
    master::EventQueue events;
    sequencer::MailboxServiceOptions options;
    options.emergency_poll = std::chrono::milliseconds(1);
    MailboxService service(eni, sim.bus, mailboxes, {nullptr, &events}, clock, options);
    wire::CoeEmergency emergency;
    emergency.error_code = 0xFF01;
    emergency.error_register = 0x80;
    sim.bus.with_segment([&](sim::Segment& s) { REQUIRE(s.send_emergency(2, emergency)); });
    std::vector<master::EventReport> seen;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (seen.empty() && std::chrono::steady_clock::now() < until) seen = events.pop_all(std::chrono::milliseconds(100));
    REQUIRE(seen.size() == 1);
    const auto e = sequencer::CoeEmergencyEvent::from(seen[0].event);
    CHECK(e.slave == 1);
    CHECK(e.emergency == emergency);
}

}  // namespace
}  // namespace ecpair::test
