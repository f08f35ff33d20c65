// Fuzz target: arbitrary bytes as the SM0 contents a slave stack's mailbox
// server receives, with its CoE, FoE, EoE and SoE servers behind it. The
// servers (one per mailbox size, from too small for any SDO reply to the
// 1004 bytes of a real ENI) keep their state between inputs, so sequences
// reach segmented transfers, FoE reads and writes, SoE fragments,
// retransmissions and waiting replies. The first input byte picks the
// server and the AL state and may stop the mailbox, let the master read SM1
// first, or make the slave send an emergency. Every reply must fit SM1 and
// be a whole mailbox message (its header's length inside the reply).

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <numeric>

#include "ecpair/sim/coe_server.hpp"
#include "ecpair/sim/eoe_server.hpp"
#include "ecpair/sim/esc.hpp"
#include "ecpair/sim/foe_server.hpp"
#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/sim/soe_server.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace {

using namespace ecpair;

class CheckingOutbox final : public sim::MailboxOutbox {
public:
    explicit CheckingOutbox(std::size_t sm1_size) : sm1_size_(sm1_size) {}

    bool post(ConstBytes reply) override {
        if (full_) return false;
        const auto header = wire::MailboxHeader::decode(reply);
        if (reply.size() > sm1_size_ || !header || wire::MailboxHeader::kSize + header->length > reply.size()) {
            std::abort();
        }
        full_ = true;
        return true;
    }
    bool full() const override { return full_; }
    void master_read() { full_ = false; }

private:
    std::size_t sm1_size_;
    bool full_ = false;
};

class FakeSlave final : public sim::CoeSlaveContext {
public:
    std::uint16_t station_address() const override { return 0x1001; }
    eni::SlaveState al_state() const override { return state; }
    void process_data_size_changed(std::uint8_t, std::optional<std::uint16_t>) override {}

    eni::SlaveState state = eni::SlaveState::Preop;
};

eni::CoeInitCmd init_cmd(std::uint16_t index, std::uint8_t subindex, std::size_t size, bool complete_access = false) {
    eni::CoeInitCmd cmd;
    cmd.index = index;
    cmd.subindex = subindex;
    cmd.complete_access = complete_access;
    cmd.data.resize(size);
    std::iota(cmd.data.begin(), cmd.data.end(), std::uint8_t{1});
    return cmd;
}

// A drive with PDOs, a vendor record, a long vendor object and a PDO mapping made by a CompleteAccess InitCmd.
sim::EscDescription drive() {
    sim::EscDescription d;
    d.name = "fuzzed drive";
    eni::Mailbox mailbox;
    mailbox.send = eni::MailboxArea{0x1000, 128};
    mailbox.recv = eni::MailboxArea{0x1080, 128};
    mailbox.protocols = eni::kCoE | eni::kFoE | eni::kEoE | eni::kSoE;
    mailbox.coe_init_cmds = {init_cmd(0x2000, 0, 300), init_cmd(0x2001, 1, 2), init_cmd(0x2001, 3, 4),
                             init_cmd(0x1601, 0, 2 + 4 * 8, true)};
    d.mailbox = mailbox;
    eni::Pdo rx;
    rx.index = 0x1600;
    rx.sm = 2;
    rx.entries = {eni::PdoEntry{0x7000, 1, 16, "out", "UINT"}, eni::PdoEntry{0, 0, 8, "", ""}};
    eni::Pdo tx;
    tx.index = 0x1A00;
    tx.sm = 3;
    tx.entries = {eni::PdoEntry{0x6000, 0, 32, "in", "UDINT"}};
    d.process_data.rx_pdos = {rx};
    d.process_data.tx_pdos = {tx};
    return d;
}

eni::SoeInitCmd soe_cmd(std::uint8_t drive, std::uint16_t idn, std::size_t size) {
    eni::SoeInitCmd cmd;
    cmd.drive_no = drive;
    cmd.idn = idn;
    cmd.data.assign(size, 0x5A);
    return cmd;
}

std::vector<std::unique_ptr<sim::MailboxProtocol>> protocols(sim::CoeSlaveContext& slave, std::size_t sm1_size) {
    std::vector<std::unique_ptr<sim::MailboxProtocol>> all;
    all.push_back(std::make_unique<sim::CoeServer>(sim::ObjectDictionary::for_slave(drive()), slave, sm1_size));
    auto foe = std::make_unique<sim::FoeServer>(sm1_size, sm1_size, 4096);
    foe->put_file("fw", std::vector<std::uint8_t>(300, 0x11));
    all.push_back(std::move(foe));
    all.push_back(std::make_unique<sim::EoeServer>());
    all.push_back(std::make_unique<sim::SoeServer>(std::vector<eni::SoeInitCmd>{soe_cmd(0, 32, 2), soe_cmd(1, 0x8001, 600)}));
    return all;
}

struct Target {
    explicit Target(std::size_t sm1_size) : outbox(sm1_size), server(slave, sm1_size, protocols(slave, sm1_size)) {}
    FakeSlave slave;
    CheckingOutbox outbox;
    sim::MailboxServer server;
};

constexpr std::array<std::size_t, 5> kSm1Sizes = {9, 16, 40, 128, 1004};
constexpr std::array<eni::SlaveState, 4> kStates = {eni::SlaveState::Preop, eni::SlaveState::Safeop,
                                                     eni::SlaveState::Op, eni::SlaveState::Boot};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static std::array<std::unique_ptr<Target>, kSm1Sizes.size()> targets = [] {
        std::array<std::unique_ptr<Target>, kSm1Sizes.size()> made;
        for (std::size_t i = 0; i < made.size(); ++i) made[i] = std::make_unique<Target>(kSm1Sizes[i]);
        return made;
    }();
    if (size == 0) return 0;

    // Byte 0: bits 0-2 the server, bits 3-4 the AL state, bit 5 stops the
    // mailbox first, bit 6 lets the master read SM1 first, bit 7 sends an
    // emergency first.
    const std::uint8_t control = data[0];
    Target& target = *targets[(control & 0x07u) % targets.size()];
    target.slave.state = kStates[(control >> 3) & 0x03u];
    if ((control & 0x20u) != 0) target.server.on_stopped();
    if ((control & 0x40u) != 0) {
        target.outbox.master_read();
        target.server.on_reply_read(target.outbox);
    }
    if ((control & 0x80u) != 0) {
        wire::CoeEmergency emergency;
        emergency.error_code = 0x8130;
        (void)target.server.send_unsolicited(wire::MailboxType::CoE, sim::CoeServer::emergency(emergency),
                                             target.outbox);
    }
    target.server.on_request(ConstBytes(data + 1, size - 1), target.outbox);
    return 0;
}
