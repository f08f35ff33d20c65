// The slave stack's mailbox server and its FoE, EoE and SoE servers, driven
// directly (an outbox standing for SM1): the queue behind an unread reply,
// emergencies in it, retransmissions, and the FoE state machine's errors
// (packet numbers, a full store, messages out of place). The same servers
// answer the master's clients over the simulated segment in
// tests/sequencer/mailbox_protocols_segment_tests.cpp.

#include <catch2/catch.hpp>

#include <deque>

#include "ecpair/sim/coe_server.hpp"
#include "ecpair/sim/eoe_server.hpp"
#include "ecpair/sim/esc.hpp"
#include "ecpair/sim/foe_server.hpp"
#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/sim/soe_server.hpp"
#include "ecpair/wire/foe.hpp"

using namespace ecpair;
using namespace ecpair::sim;

namespace {

constexpr std::size_t kSm = 128;

class Sm1 final : public MailboxOutbox {
public:
    bool post(ConstBytes reply) override {
        if (full_) return false;
        full_ = true;
        posted.emplace_back(reply.begin(), reply.end());
        return true;
    }
    bool full() const override { return full_; }
    void read() { full_ = false; }

    std::vector<std::vector<std::uint8_t>> posted;

private:
    bool full_ = false;
};

class Slave final : public CoeSlaveContext {
public:
    std::uint16_t station_address() const override { return 1001; }
    eni::SlaveState al_state() const override { return state; }
    void process_data_size_changed(std::uint8_t, std::optional<std::uint16_t>) override {}
    eni::SlaveState state = eni::SlaveState::Preop;
};

std::vector<std::uint8_t> request(wire::MailboxType type, ConstBytes body, std::uint8_t counter) {
    std::vector<std::uint8_t> out(kSm, 0);
    wire::MailboxHeader{static_cast<std::uint16_t>(body.size()), 0, 0, 0, type, counter}.encode(out);
    std::copy(body.begin(), body.end(), out.begin() + wire::MailboxHeader::kSize);
    return out;
}

struct Stack {
    Slave slave;
    Sm1 sm1;
    FoeServer* foe = nullptr;
    std::unique_ptr<MailboxServer> server;
    std::uint8_t counter = 0;

    explicit Stack(std::size_t foe_room = FoeServer::kDefaultRoom) {
        std::vector<std::unique_ptr<MailboxProtocol>> protocols;
        protocols.push_back(std::make_unique<CoeServer>(ObjectDictionary::for_slave(EscDescription{}), slave, kSm));
        auto foe_server = std::make_unique<FoeServer>(kSm, kSm, foe_room);
        foe = foe_server.get();
        protocols.push_back(std::move(foe_server));
        protocols.push_back(std::make_unique<EoeServer>());
        server = std::make_unique<MailboxServer>(slave, kSm, std::move(protocols));
    }
    // Sends a request; the reply the master reads (nullopt: none in SM1).
    std::optional<wire::FoeMessage> foe_exchange(const wire::FoeMessage& message) {
        counter = wire::next_mailbox_counter(counter);
        server->on_request(request(wire::MailboxType::FoE, wire::encode_foe(message), counter), sm1);
        return read_foe();
    }
    std::optional<wire::FoeMessage> read_foe() {
        if (!sm1.full()) return std::nullopt;
        const auto& reply = sm1.posted.back();
        sm1.read();
        server->on_reply_read(sm1);
        const auto header = wire::MailboxHeader::decode(reply);
        REQUIRE(header);
        REQUIRE(header->type == wire::MailboxType::FoE);
        return wire::decode_foe(ConstBytes(reply).subspan(wire::MailboxHeader::kSize, header->length));
    }
};

std::uint32_t error_code(const std::optional<wire::FoeMessage>& m) {
    REQUIRE(m);
    REQUIRE(std::holds_alternative<wire::FoeError>(*m));
    return std::get<wire::FoeError>(*m).code;
}

}  // namespace

TEST_CASE("an emergency waits behind an unread reply and keeps the counter order", "[esc][mailbox]") {
    Stack stack;
    stack.server->on_request(request(wire::MailboxType::EoE, std::vector<std::uint8_t>{0x06, 0x01, 0, 0}, 1), stack.sm1);
    wire::CoeEmergency emergency;
    emergency.error_code = 0x8130;
    REQUIRE(stack.server->send_unsolicited(wire::MailboxType::CoE, CoeServer::emergency(emergency), stack.sm1));
    REQUIRE(stack.sm1.posted.size() == 1);  // the EoE answer sits in SM1; the emergency waits
    stack.sm1.read();
    stack.server->on_reply_read(stack.sm1);
    REQUIRE(stack.sm1.posted.size() == 2);
    const auto first = wire::MailboxHeader::decode(stack.sm1.posted[0]);
    const auto second = wire::MailboxHeader::decode(stack.sm1.posted[1]);
    CHECK(first->type == wire::MailboxType::EoE);
    CHECK(second->type == wire::MailboxType::CoE);
    CHECK(second->address == 1001);
    CHECK(second->counter == wire::next_mailbox_counter(first->counter));
    const auto body = ConstBytes(stack.sm1.posted[1]).subspan(wire::MailboxHeader::kSize, second->length);
    CHECK(wire::CoeHeader::decode(body)->service == wire::CoeService::Emergency);
    CHECK(wire::CoeEmergency::decode(body.subspan(wire::CoeHeader::kSize)) == emergency);

    // The queue is bounded: a master that never reads does not make the slave grow.
    std::size_t accepted = 0;
    while (stack.server->send_unsolicited(wire::MailboxType::CoE, CoeServer::emergency(emergency), stack.sm1)) ++accepted;
    CHECK(accepted == MailboxServer::kMaxQueued);
}

TEST_CASE("FoE: the slave's state machine refuses what does not fit its state", "[esc][mailbox][foe]") {
    Stack stack;
    CHECK(error_code(stack.foe_exchange(wire::FoeAck{1})) == wire::foe_error::kIllegal);
    CHECK(error_code(stack.foe_exchange(wire::FoeData{1, {1}})) == wire::foe_error::kIllegal);
    CHECK(error_code(stack.foe_exchange(wire::FoeWriteRequest{0, ""})) == wire::foe_error::kIllegal);
    CHECK(error_code(stack.foe_exchange(wire::FoeBusy{})) == wire::foe_error::kIllegal);

    // A write whose second packet comes with the wrong number.
    REQUIRE(std::get<wire::FoeAck>(*stack.foe_exchange(wire::FoeWriteRequest{0, "a"})).packet == 0);
    const std::vector<std::uint8_t> full(kSm - 12, 7);
    REQUIRE(std::get<wire::FoeAck>(*stack.foe_exchange(wire::FoeData{1, full})).packet == 1);
    CHECK(error_code(stack.foe_exchange(wire::FoeData{3, {1}})) == wire::foe_error::kPacketNumberWrong);
    CHECK(stack.foe->files().empty());  // nothing stored from the broken write

    // The master gives up a read: no answer, and the next read starts from packet 1.
    stack.foe->put_file("f", std::vector<std::uint8_t>(300, 1));
    REQUIRE(std::get<wire::FoeData>(*stack.foe_exchange(wire::FoeReadRequest{0, "f"})).packet == 1);
    CHECK_FALSE(stack.foe_exchange(wire::FoeError{wire::foe_error::kNotDefined, "stop"}));
    CHECK(error_code(stack.foe_exchange(wire::FoeAck{1})) == wire::foe_error::kIllegal);
    REQUIRE(std::get<wire::FoeData>(*stack.foe_exchange(wire::FoeReadRequest{0, "f"})).packet == 1);
    CHECK(error_code(stack.foe_exchange(wire::FoeAck{2})) == wire::foe_error::kPacketNumberWrong);
}

TEST_CASE("FoE: a file larger than the store's room ends with disk full, replacing a file counts once",
          "[esc][mailbox][foe]") {
    Stack stack(500);
    const std::vector<std::uint8_t> full(kSm - 12, 7);
    const auto write = [&](const std::string& name, std::size_t packets) -> std::optional<wire::FoeMessage> {
        REQUIRE(std::get<wire::FoeAck>(*stack.foe_exchange(wire::FoeWriteRequest{0, name})).packet == 0);
        std::optional<wire::FoeMessage> last;
        for (std::uint32_t p = 1; p <= packets; ++p) {
            last = stack.foe_exchange(wire::FoeData{p, p == packets ? std::vector<std::uint8_t>{1} : full});
            if (!last || std::holds_alternative<wire::FoeError>(*last)) break;
        }
        return last;
    };
    REQUIRE(std::holds_alternative<wire::FoeAck>(*write("a", 4)));  // 3 x 116 + 1 = 349 bytes
    CHECK(stack.foe->files().at("a").size() == 349);
    REQUIRE(std::holds_alternative<wire::FoeAck>(*write("a", 4)));  // the same name again: replaced
    CHECK(error_code(write("b", 3)) == wire::foe_error::kDiskFull);
    CHECK(stack.foe->files().count("b") == 0);
}

TEST_CASE("FoE runs in BOOT, CoE does not, a request repeating the counter gets the last reply again",
          "[esc][mailbox][foe]") {
    Stack stack;
    stack.slave.state = eni::SlaveState::Boot;
    stack.foe->put_file("boot.efw", {1, 2, 3});
    REQUIRE(std::get<wire::FoeData>(*stack.foe_exchange(wire::FoeReadRequest{0, "boot.efw"})).data ==
            std::vector<std::uint8_t>{1, 2, 3});
    const auto before = stack.sm1.posted.size();
    stack.server->on_request(request(wire::MailboxType::FoE, wire::encode_foe(wire::FoeReadRequest{0, "x"}), stack.counter),
                             stack.sm1);
    REQUIRE(stack.sm1.posted.size() == before + 1);
    CHECK(stack.sm1.posted.back() == stack.sm1.posted[before - 1]);  // the DATA again, not a new answer
    stack.sm1.read();

    stack.server->on_request(request(wire::MailboxType::CoE, std::vector<std::uint8_t>{0x00, 0x20, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0}, 5),
                             stack.sm1);
    const auto header = wire::MailboxHeader::decode(stack.sm1.posted.back());
    CHECK(header->type == wire::MailboxType::Error);
    CHECK(wire::MailboxErrorReply::decode(ConstBytes(stack.sm1.posted.back()).subspan(6))->detail == 0x0002);
}
