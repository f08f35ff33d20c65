// The PDI-side mailbox seam: the default error reply, an installed handler,
// outbox semantics, repeat requests, stopping.

#include <memory>

#include <catch2/catch.hpp>

#include "ecpair/wire/mailbox.hpp"
#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

constexpr std::uint16_t kSm0 = 0x1000;
constexpr std::uint16_t kSm1 = 0x1080;

std::vector<std::uint8_t> request(wire::MailboxType type, std::uint16_t length, std::uint8_t counter) {
    std::vector<std::uint8_t> r(128, 0);
    wire::MailboxHeader{length, 0, 0, 0, type, counter}.encode(r);
    r[6] = 0xAB;
    return r;
}

Line drive_in_preop() {
    Line line({drive_description()});
    line.assign_station_addresses();
    REQUIRE(bring_drive_to(line, kFirstStation, 0x02) == 0x02);
    return line;
}

Datagram read_sm1(Line& line) { return line.transact(physical_read(Command::Fprd, kFirstStation, kSm1, 128)); }

struct Record {
    std::vector<std::vector<std::uint8_t>> requests;
    int replies_read = 0;
    int stopped = 0;
    bool second_post_refused = false;
};

// Answers every request with its first 8 bytes and tries a second reply at once.
class EchoHandler final : public MailboxHandler {
public:
    explicit EchoHandler(std::shared_ptr<Record> record) : record_(std::move(record)) {}
    void on_request(ConstBytes request, MailboxOutbox& outbox) override {
        record_->requests.emplace_back(request.begin(), request.end());
        outbox.post(request.first(8));
        record_->second_post_refused = !outbox.post(request.first(8)) && outbox.full();
    }
    void on_reply_read(MailboxOutbox&) override { ++record_->replies_read; }
    void on_stopped() override { ++record_->stopped; }

private:
    std::shared_ptr<Record> record_;
};

}  // namespace

TEST_CASE("without a handler every request gets a mailbox error reply, as from SOES") {
    Line line = drive_in_preop();
    line[0].set_mailbox_handler(nullptr);  // the drive offers CoE and would get ecsim's CoE server
    REQUIRE(line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::CoE, 10, 1)) == 1);
    const Datagram reply = read_sm1(line);
    REQUIRE(reply.wkc == 1);
    const auto header = wire::MailboxHeader::decode(reply.data);
    REQUIRE(header);
    CHECK(header->type == wire::MailboxType::Error);
    CHECK(header->length == 4);
    CHECK(header->counter == 1);
    CHECK(load_le<std::uint16_t>(reply.data, 6) == 0x0001);
    CHECK(load_le<std::uint16_t>(reply.data, 8) == 0x0002);  // unsupported protocol

    line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::Error, 10, 2));
    const Datagram invalid = read_sm1(line);
    CHECK(wire::MailboxHeader::decode(invalid.data)->counter == 2);
    CHECK(load_le<std::uint16_t>(invalid.data, 8) == 0x0005);  // invalid header

    line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::CoE, 500, 3));  // longer than the mailbox
    CHECK(load_le<std::uint16_t>(read_sm1(line).data, 8) == 0x0005);

    line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::CoE, 10, 3));  // a retransmission
    CHECK(read_sm1(line).wkc == 0);
}

TEST_CASE("an installed handler gets each request at the end of its frame and answers through SM1") {
    Line line = drive_in_preop();
    auto record = std::make_shared<Record>();
    line[0].set_mailbox_handler(std::make_unique<EchoHandler>(record));

    const auto sent = request(wire::MailboxType::CoE, 10, 1);
    line.fpwr(kFirstStation, kSm0, sent);
    REQUIRE(record->requests.size() == 1);
    CHECK(record->requests[0] == sent);
    CHECK(record->second_post_refused);
    CHECK(record->replies_read == 0);

    const Datagram reply = read_sm1(line);
    CHECK(reply.wkc == 1);
    CHECK(std::vector<std::uint8_t>(reply.data.begin(), reply.data.begin() + 8) ==
          std::vector<std::uint8_t>(sent.begin(), sent.begin() + 8));
    CHECK(std::vector<std::uint8_t>(reply.data.begin() + 8, reply.data.end()) == std::vector<std::uint8_t>(120, 0));
    CHECK(record->replies_read == 1);

    CHECK(line[0].post_mailbox_reply(bytes({1, 2, 3})));
    CHECK_FALSE(line[0].post_mailbox_reply(bytes({4, 5, 6})));
    CHECK(read_sm1(line).data[2] == 3);
}

TEST_CASE("a repeat request makes the slave write its last reply again") {
    Line line = drive_in_preop();
    line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::CoE, 10, 1));
    const Datagram first = read_sm1(line);
    REQUIRE(first.wkc == 1);
    REQUIRE(read_sm1(line).wkc == 0);  // "lost" on its way back: the master asks again

    const std::uint8_t activate = line.fprd(kFirstStation, 0x080E, 1)[0];
    line.fpwr(kFirstStation, 0x080E, {static_cast<std::uint8_t>(activate ^ 0x02)});
    CHECK((line.fprd(kFirstStation, 0x080F, 1)[0] & 0x02) == ((activate ^ 0x02) & 0x02));  // acknowledged
    const Datagram again = read_sm1(line);
    CHECK(again.wkc == 1);
    CHECK(again.data == first.data);
}

TEST_CASE("the mailbox stops outside PREOP/SAFEOP/OP/BOOT and the handler hears it") {
    Line line = drive_in_preop();
    auto record = std::make_shared<Record>();
    line[0].set_mailbox_handler(std::make_unique<EchoHandler>(record));
    line.fpwr(kFirstStation, 0x0120, le16(0x0001));
    CHECK(record->stopped == 1);
    CHECK_FALSE(line[0].post_mailbox_reply(bytes({1})));
    CHECK(line.fpwr(kFirstStation, kSm0, request(wire::MailboxType::CoE, 10, 1)) == 0);
    CHECK(record->requests.empty());
}
