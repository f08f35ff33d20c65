// SdoClient and CoeInitCmdRunner against the fake mailbox slave: every
// transfer form, aborts, mailbox errors, a full SM0, emergencies,
// timeouts, the mailbox counter, and the Ccs dialects of CoE InitCmds.

#include <catch2/catch.hpp>

#include <numeric>

#include "ecpair/sequencer/coe_init_cmd_runner.hpp"
#include "ecpair/sequencer/sdo_client.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "fake_mailbox_slave.hpp"
#include "fakes.hpp"

namespace ecpair::test {
namespace {

using sequencer::SdoClient;
using sequencer::SdoFailure;

std::vector<std::uint8_t> counting_bytes(std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    std::iota(bytes.begin(), bytes.end(), std::uint8_t{1});
    return bytes;
}

struct SdoFixture {
    FakeMailboxSlave slave;
    VirtualClock clock;
    sequencer::MailboxTransport transport{slave, clock, FakeMailboxSlave::channel()};
    SdoClient client{transport, clock};
};

TEST_CASE_METHOD(SdoFixture, "SDO download: expedited, normal and segmented", "[sequencer][sdo]") {
    SECTION("expedited") {
        slave.objects[{0x6060, 0}] = {0x00};
        REQUIRE(client.download(0x6060, 0, std::vector<std::uint8_t>{0x08}, false));
        CHECK(slave.objects[{0x6060, 0}] == std::vector<std::uint8_t>{0x08});
        REQUIRE(slave.requests.size() == 1);
        CHECK(slave.requests[0].expedited);
    }
    SECTION("normal: fits the first message") {
        slave.objects[{0x2000, 1}] = {};
        const auto data = counting_bytes(20);
        REQUIRE(client.download(0x2000, 1, data, false));
        CHECK(slave.objects[{0x2000, 1}] == data);
        REQUIRE(slave.requests.size() == 1);
        CHECK_FALSE(slave.requests[0].expedited);
        CHECK(slave.requests[0].complete_size == 20);
    }
    SECTION("segmented: 300 bytes through a 128-byte mailbox") {
        slave.objects[{0x2001, 0}] = {};
        const auto data = counting_bytes(300);
        REQUIRE(client.download(0x2001, 0, data, false));
        CHECK(slave.objects[{0x2001, 0}] == data);
        // 112 bytes in the initiate message, then segments of 119 and 69 bytes.
        REQUIRE(slave.requests.size() == 3);
        CHECK(slave.requests[0].complete_size == 300);
        CHECK(slave.requests[0].data.size() == 112);
        CHECK(slave.requests[1].command == wire::SdoCommand::DownloadSegment);
        CHECK_FALSE(slave.requests[1].toggle);
        CHECK_FALSE(slave.requests[1].last_segment);
        CHECK(slave.requests[2].toggle);
        CHECK(slave.requests[2].last_segment);
    }
    SECTION("complete access is a normal transfer with the CA flag") {
        slave.objects[{0x1c12, 0}] = {};
        const std::vector<std::uint8_t> assign = {0x01, 0x00, 0x02, 0x16};
        REQUIRE(client.download(0x1c12, 0, assign, true));
        CHECK(slave.objects[{0x1c12, 0}] == assign);
        REQUIRE(slave.requests.size() == 1);
        CHECK(slave.requests[0].complete_access);
        CHECK_FALSE(slave.requests[0].expedited);
    }
}

TEST_CASE_METHOD(SdoFixture, "SDO upload: expedited, normal and segmented", "[sequencer][sdo]") {
    slave.objects[{0x1000, 0}] = {0x92, 0x01, 0x02, 0x00};
    slave.objects[{0x1008, 0}] = counting_bytes(50);
    slave.objects[{0x2002, 0}] = counting_bytes(300);

    auto small = client.upload(0x1000, 0, false);
    REQUIRE(small);
    CHECK(*small == slave.objects[{0x1000, 0}]);

    auto normal = client.upload(0x1008, 0, false);
    REQUIRE(normal);
    CHECK(*normal == slave.objects[{0x1008, 0}]);

    const auto before = slave.requests.size();
    auto segmented = client.upload(0x2002, 0, false);
    REQUIRE(segmented);
    CHECK(*segmented == slave.objects[{0x2002, 0}]);
    // 112 bytes with the answer to the initiate, then 119 and 69 in two segments.
    CHECK(slave.requests.size() - before == 3);
}

TEST_CASE_METHOD(SdoFixture, "SDO abort and mailbox error come back with their texts", "[sequencer][sdo]") {
    SECTION("abort") {
        const auto result = client.download(0x7000, 1, std::vector<std::uint8_t>{1, 2}, false);
        REQUIRE_FALSE(result);
        CHECK(result.error().failure == SdoFailure::Abort);
        CHECK(result.error().abort_code == wire::sdo_abort::kObjectDoesNotExist);
        CHECK_THAT(result.error().message,
                   Catch::Equals("SDO 0x7000:01 download: aborted: 0x06020000 object does not exist in the object dictionary"));
    }
    SECTION("mailbox error") {
        slave.objects[{0x6060, 0}] = {0};
        slave.mailbox_error = 2;
        const auto result = client.upload(0x6060, 0, false);
        REQUIRE_FALSE(result);
        CHECK(result.error().failure == SdoFailure::MailboxError);
        CHECK(result.error().mailbox_error == 2);
        CHECK_THAT(result.error().message, Catch::Contains("mailbox protocol not supported"));
    }
}

TEST_CASE_METHOD(SdoFixture, "A full SM0 is written again until the slave takes it", "[sequencer][sdo]") {
    slave.objects[{0x6060, 0}] = {0};
    slave.sm0_busy_writes = 3;
    REQUIRE(client.download(0x6060, 0, std::vector<std::uint8_t>{8}, false));
    CHECK(slave.sm0_writes_refused == 3);
    CHECK(slave.objects[{0x6060, 0}] == std::vector<std::uint8_t>{8});
}

TEST_CASE_METHOD(SdoFixture, "An emergency before the answer goes to the emergency handler", "[sequencer][sdo]") {
    slave.objects[{0x6060, 0}] = {0};
    slave.emergency_first = true;
    std::vector<wire::CoeEmergency> emergencies;
    transport.set_emergency_handler([&emergencies](const wire::CoeEmergency& e) { emergencies.push_back(e); });
    REQUIRE(client.download(0x6060, 0, std::vector<std::uint8_t>{8}, false));
    REQUIRE(emergencies.size() == 1);
    CHECK(emergencies[0].error_code == 0x8110);
}

TEST_CASE_METHOD(SdoFixture, "No answer: timeout", "[sequencer][sdo]") {
    slave.objects[{0x6060, 0}] = {0};
    slave.answer = false;
    const auto result = client.download(0x6060, 0, std::vector<std::uint8_t>{8}, false, std::chrono::milliseconds(50));
    REQUIRE_FALSE(result);
    CHECK(result.error().failure == SdoFailure::Timeout);
    CHECK_THAT(result.error().message, Catch::Contains("no mailbox reply from station 1001"));
}

TEST_CASE_METHOD(SdoFixture, "The mailbox counter runs 1..7 and wraps to 1", "[sequencer][sdo]") {
    slave.objects[{0x6060, 0}] = {0};
    for (int i = 0; i < 8; ++i) REQUIRE(client.download(0x6060, 0, std::vector<std::uint8_t>{1}, false));
    CHECK(slave.counters == std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 1});
}

TEST_CASE("after a takeover the SDO client continues after the partner's counter and drops its stale reply",
          "[sequencer][sdo]") {
    FakeMailboxSlave slave;
    VirtualClock clock;
    slave.objects[{0x6000, 1}] = {0x11, 0x22};
    slave.objects[{0x6000, 2}] = {0x33};
    // The old ACTIVE's last request (upload 0x6000:02), sent with counter 5;
    // it lost the bus before it read the reply, which waits in SM1.
    wire::SdoMessage upload;
    upload.command = wire::SdoCommand::Upload;
    upload.index = 0x6000;
    upload.subindex = 2;
    std::vector<std::uint8_t> request(wire::MailboxHeader::kSize + wire::CoeHeader::kSize + upload.encoded_size());
    wire::MailboxHeader{static_cast<std::uint16_t>(request.size() - wire::MailboxHeader::kSize), 0, 0, 0,
                        wire::MailboxType::CoE, 5}
        .encode(request);
    wire::CoeHeader{0, wire::CoeService::SdoRequest}.encode(std::span(request).subspan(wire::MailboxHeader::kSize));
    upload.encode(std::span(request).subspan(wire::MailboxHeader::kSize + wire::CoeHeader::kSize));
    sequencer::MailboxTransport old_master(slave, clock, FakeMailboxSlave::channel());
    REQUIRE(old_master.send(request, clock.now() + std::chrono::seconds(1), {}));

    sequencer::MailboxTransport new_transport(slave, clock, FakeMailboxSlave::channel());
    new_transport.continue_after(5);
    SdoClient new_master(new_transport, clock);
    const auto value = new_master.upload(0x6000, 1, false);
    REQUIRE(value);
    CHECK(*value == std::vector<std::uint8_t>{0x11, 0x22});
    CHECK(slave.counters.back() == 6);  // not a repeat of the old ACTIVE's 5
}

TEST_CASE_METHOD(SdoFixture, "CoE InitCmds: Ccs 1 downloads, Ccs 2 with data downloads, Ccs 2 without data uploads",
                 "[sequencer][sdo][coe]") {
    sequencer::CoeInitCmdRunner runner;
    slave.objects[{0x8000, 1}] = {0, 0};
    slave.objects[{0x1018, 1}] = {0x02, 0x00, 0x00, 0x00};
    eni::CoeInitCmd cmd;
    cmd.index = 0x8000;
    cmd.subindex = 1;
    cmd.data = {0x34, 0x12};
    cmd.source_line = 12;

    cmd.ccs = 1;
    REQUIRE(runner.run(client, cmd, "slave 'IO'"));
    CHECK(slave.objects[{0x8000, 1}] == std::vector<std::uint8_t>{0x34, 0x12});

    cmd.ccs = 2;  // Advantech: upload code, write data
    cmd.data = {0x78, 0x56};
    REQUIRE(runner.run(client, cmd, "slave 'IO'"));
    CHECK(slave.objects[{0x8000, 1}] == std::vector<std::uint8_t>{0x78, 0x56});
    CHECK(slave.requests.back().command == wire::SdoCommand::Download);

    eni::CoeInitCmd read;
    read.ccs = 2;
    read.index = 0x1018;
    read.subindex = 1;
    REQUIRE(runner.run(client, read, "slave 'IO'"));
    CHECK(slave.requests.back().command == wire::SdoCommand::Upload);

    SECTION("a failure names the ENI line and the SDO") {
        eni::CoeInitCmd bad = cmd;
        bad.index = 0x9999;
        bad.comment = "set gain";
        const auto result = runner.run(client, bad, "slave 'IO'");
        REQUIRE_FALSE(result);
        CHECK_THAT(result.error().describe(),
                   Catch::StartsWith("slave 'IO', ENI line 12 'set gain': SDO 0x9999:01 download: aborted: 0x06020000"));
    }
    SECTION("disabled commands are skipped") {
        eni::CoeInitCmd off = cmd;
        off.index = 0x9999;
        off.disabled = true;
        const auto count = slave.requests.size();
        REQUIRE(runner.run(client, off, "slave 'IO'"));
        CHECK(slave.requests.size() == count);
    }
}

}  // namespace
}  // namespace ecpair::test
