// The protocol clients against the simulated slaves' servers (sim/esc),
// over the simulated segment: a drive whose mailbox offers CoE, FoE, EoE and
// SoE (tests/data/eni_extra/soe_eoe_drive_2slaves.xml), brought to PREOP by
// the state machine (which runs its SoE and EoE InitCmds on the way to
// SAFEOP), then SDO Information, FoE (a file written and read back, the
// password, a missing file, a busy slave), SoE (values, a
// fragmented one, errors), EoE and emergencies, each as a master sees it.

#include <catch2/catch.hpp>

#include <numeric>

#include "ecpair/sequencer/eoe_client.hpp"
#include "ecpair/sequencer/foe_client.hpp"
#include "ecpair/sequencer/sdo_information_client.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sequencer/soe_client.hpp"
#include "ecpair/sim/eoe_server.hpp"
#include "ecpair/sim/soe_server.hpp"
#include "ecpair/wire/foe.hpp"
#include "fakes.hpp"
#include "segment_fixture.hpp"

namespace ecpair::test {
namespace {

using sequencer::MasterState;
using sequencer::ProtocolFailure;

constexpr std::size_t kDrive = 1;  // ENI index of the drive
constexpr std::chrono::milliseconds kTimeout{500};

std::vector<std::uint8_t> counting(std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    std::iota(bytes.begin(), bytes.end(), std::uint8_t{1});
    return bytes;
}

struct DriveBus {
    std::shared_ptr<const eni::EniConfig> eni = load_eni_copy("eni_extra/soe_eoe_drive_2slaves.xml");
    SimulatedBus sim{*eni};
    VirtualClock clock;
    sequencer::SlaveMailboxes mailboxes{*eni, sim.bus, clock};

    explicit DriveBus(MasterState state = MasterState::Preop) {
        sequencer::StateMachineOptions options;
        options.mailboxes = &mailboxes;
        sequencer::MasterStateMachine machine(eni, sim.bus, {}, nullptr, clock, options);
        const auto error = run_to(machine, state);
        INFO((error ? error->message : std::string()));
        REQUIRE_FALSE(error);
    }
    sequencer::SlaveMailbox::Session drive() { return mailboxes.find(kDrive)->open(); }
    void foe_password(std::uint32_t password) {
        sim.bus.with_segment([password](sim::Segment& s) { REQUIRE(s.set_foe_password(kDrive + 1, password)); });
    }
    void foe_busy(std::uint32_t packets) {
        sim.bus.with_segment([packets](sim::Segment& s) { REQUIRE(s.set_foe_busy(kDrive + 1, packets)); });
    }
};

TEST_CASE("SDO Information: the object list and the descriptions of the drive's objects", "[sequencer][mailbox][segment]") {
    DriveBus bus;
    auto session = bus.drive();
    sequencer::SdoInformationClient info(session.transport(), bus.clock);
    const auto list = info.object_list(wire::OdListType::All, kTimeout);
    REQUIRE(list);
    CHECK(std::find(list->begin(), list->end(), 0x1018) != list->end());
    CHECK(std::is_sorted(list->begin(), list->end()));
    const auto identity = info.object_description(0x1018, kTimeout);
    REQUIRE(identity);
    CHECK(identity->object_code == wire::kObjectCodeRecord);
    CHECK(identity->max_subindex == 4);
    const auto vendor = info.entry_description(0x1018, 1, kTimeout);
    REQUIRE(vendor);
    CHECK(vendor->data_type == wire::coe_type::kUnsigned32);
    CHECK(vendor->bit_length == 32);

    const auto missing = info.object_description(0x5FFF, kTimeout);
    REQUIRE_FALSE(missing);
    CHECK(missing.error().failure == sequencer::SdoFailure::Abort);
    CHECK(missing.error().abort_code == wire::sdo_abort::kObjectDoesNotExist);
    CHECK_THAT(missing.error().message, Catch::Contains("SDO Information object 0x5fff: aborted: 0x06020000"));
}

TEST_CASE("FoE: a file written in several packets reads back the same", "[sequencer][mailbox][segment][foe]") {
    DriveBus bus;
    auto session = bus.drive();
    sequencer::FoeClient foe(session.transport(), bus.clock);
    // The drive's mailbox is 128 bytes: 116 bytes per packet.
    for (const std::size_t size : {std::size_t{0}, std::size_t{50}, std::size_t{116}, std::size_t{1000}}) {
        INFO(size << " bytes");
        const auto data = counting(size);
        REQUIRE(foe.write("app.bin", 0, data, kTimeout));
        const auto back = foe.read("app.bin", 0, 1 << 20, kTimeout);
        REQUIRE(back);
        CHECK(*back == data);
    }
}

TEST_CASE("FoE errors: a missing file, a wrong password, a file past the limit",
          "[sequencer][mailbox][segment][foe]") {
    DriveBus bus;
    auto session = bus.drive();
    sequencer::FoeClient foe(session.transport(), bus.clock);

    const auto missing = foe.read("nothing.bin", 0, 4096, kTimeout);
    REQUIRE_FALSE(missing);
    CHECK(missing.error().failure == ProtocolFailure::Refused);
    CHECK(missing.error().code == wire::foe_error::kNotFound);
    CHECK_THAT(missing.error().message,
               Catch::StartsWith("FoE read 'nothing.bin': the slave answered error 0x8001 file not found"));

    bus.foe_password(0x1234);
    const auto refused = foe.write("fw.efw", 1, counting(10), kTimeout);
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == wire::foe_error::kNoRights);
    REQUIRE(foe.write("fw.efw", 0x1234, counting(10), kTimeout));
    CHECK_FALSE(foe.read("fw.efw", 0, 4096, kTimeout));
    REQUIRE(foe.read("fw.efw", 0x1234, 4096, kTimeout));

    bus.foe_password(0);
    REQUIRE(foe.write("big.bin", 0, counting(400), kTimeout));
    const auto too_big = foe.read("big.bin", 0, 300, kTimeout);
    REQUIRE_FALSE(too_big);
    CHECK(too_big.error().failure == ProtocolFailure::TooLong);
    CHECK_THAT(too_big.error().message, Catch::Contains("past the 300-byte limit"));
    // The slave heard of it: the next transfer starts clean.
    REQUIRE(foe.read("big.bin", 0, 4096, kTimeout));
}

TEST_CASE("FoE: a busy slave gets its packet again until it takes it", "[sequencer][mailbox][segment][foe]") {
    DriveBus bus;
    auto session = bus.drive();
    sequencer::FoeClient foe(session.transport(), bus.clock);
    bus.foe_busy(3);
    const auto data = counting(300);
    REQUIRE(foe.write("slow.bin", 0, data, kTimeout));
    CHECK(foe.read("slow.bin", 0, 4096, kTimeout).value() == data);

    SECTION("one that stays busy past the timeout ends the write") {
        bus.foe_busy(1000);
        const auto stuck = foe.write("stuck.bin", 0, data, std::chrono::milliseconds(100));
        REQUIRE_FALSE(stuck);
        CHECK(stuck.error().failure == ProtocolFailure::Timeout);
        CHECK_THAT(stuck.error().message, Catch::Contains("stayed busy"));
    }
}

TEST_CASE("SoE: the ENI's InitCmds wrote the drives' IDNs on the way to SAFEOP", "[sequencer][mailbox][segment][soe]") {
    DriveBus bus(MasterState::Safeop);
    const sim::SoeServer* soe = nullptr;
    bus.sim.bus.with_segment([&soe](sim::Segment& s) { soe = s.slave(kDrive + 1).soe_server(); });
    REQUIRE(soe != nullptr);
    CHECK(soe->idn(0, 15)->value == std::vector<std::uint8_t>{0x07, 0x00});
    CHECK(soe->idn(0, 16)->value == std::vector<std::uint8_t>{0x04, 0x00, 0x04, 0x00, 0x33, 0x00, 0x33, 0x00});
    CHECK(soe->idn(1, 32828)->value == std::vector<std::uint8_t>{0x11, 0x00});
    std::vector<std::uint8_t> long_value(300);
    for (std::size_t i = 0; i < long_value.size(); ++i) long_value[i] = static_cast<std::uint8_t>(i);
    CHECK(soe->idn(1, 32769)->value == long_value);
    CHECK(soe->idn(0, 99)->value == std::vector<std::uint8_t>{0x00, 0x00});  // the disabled one was not run
}

TEST_CASE("SoE: values read and written, a long one in fragments, errors with their codes",
          "[sequencer][mailbox][segment][soe]") {
    DriveBus bus;
    auto session = bus.drive();
    sequencer::SoeClient soe(session.transport(), bus.clock);
    REQUIRE(soe.write(1, 32769, wire::soe_elements::kValue, counting(300), kTimeout));
    const auto back = soe.read(1, 32769, wire::soe_elements::kValue, kTimeout);
    REQUIRE(back);
    CHECK(*back == counting(300));
    const auto name = soe.read(0, 15, wire::soe_elements::kName, kTimeout);
    REQUIRE(name);
    CHECK(std::string(name->begin() + 4, name->end()) == "Telegram type parameter");

    const auto unknown = soe.read(0, 4000, wire::soe_elements::kValue, kTimeout);
    REQUIRE_FALSE(unknown);
    CHECK(unknown.error().failure == ProtocolFailure::Refused);
    CHECK(unknown.error().code == 0x1001);
    CHECK_THAT(unknown.error().message,
               Catch::Equals("SoE read S-0-4000 of drive 0: the drive answered error 0x1001 IDN not in the drive"));
    const auto no_drive = soe.write(5, 15, wire::soe_elements::kValue, counting(2), kTimeout);
    REQUIRE_FALSE(no_drive);
    CHECK(no_drive.error().code == 0x800A);
    const auto name_written = soe.write(0, 15, wire::soe_elements::kName, counting(2), kTimeout);
    REQUIRE_FALSE(name_written);
    CHECK(name_written.error().code == 0x2004);
}

TEST_CASE("EoE: the ENI's InitCmd set the IP parameters, a set and a get over the mailbox",
          "[sequencer][mailbox][segment][eoe]") {
    DriveBus bus(MasterState::Safeop);
    const auto held = [&bus] {
        wire::EoeIpParameters parameters;
        bus.sim.bus.with_segment([&](sim::Segment& s) { parameters = s.slave(kDrive + 1).eoe_server()->ip_parameters(); });
        return parameters;
    };
    REQUIRE(held().ip);
    CHECK(wire::ipv4_text(*held().ip) == "10.0.0.2");
    CHECK(wire::ipv4_text(*held().subnet) == "255.255.0.0");

    auto session = bus.drive();
    sequencer::EoeClient eoe(session.transport(), bus.clock);
    wire::EoeIpParameters set;
    set.gateway = 0x0A000001;
    set.dns_name = "drive";
    REQUIRE(eoe.set_ip_parameters(set, 0, kTimeout));
    const auto got = eoe.get_ip_parameters(0, kTimeout);
    REQUIRE(got);
    CHECK(wire::ipv4_text(*got->ip) == "10.0.0.2");  // kept: not in the second request
    CHECK(wire::ipv4_text(*got->gateway) == "10.0.0.1");
    CHECK(got->dns_name == "drive");
}

TEST_CASE("CoE emergencies reach the handler, during a transfer and when read away before a request",
          "[sequencer][mailbox][segment]") {
    DriveBus bus;
    std::vector<std::pair<std::size_t, wire::CoeEmergency>> seen;
    bus.mailboxes.set_emergency_handler(
        [&seen](std::size_t slave, const wire::CoeEmergency& e) { seen.emplace_back(slave, e); });
    wire::CoeEmergency emergency;
    emergency.error_code = 0x4210;
    emergency.error_register = 0x09;
    emergency.data = {1, 2, 3, 4, 5};
    bus.sim.bus.with_segment([&](sim::Segment& s) { REQUIRE(s.send_emergency(kDrive + 1, emergency)); });
    auto session = bus.drive();
    sequencer::SoeClient soe(session.transport(), bus.clock);
    REQUIRE(soe.read(0, 15, wire::soe_elements::kValue, kTimeout));
    REQUIRE(seen.size() == 1);
    CHECK(seen[0].first == kDrive);
    CHECK(seen[0].second == emergency);
}

}  // namespace
}  // namespace ecpair::test
