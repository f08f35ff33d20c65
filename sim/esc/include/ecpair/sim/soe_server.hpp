#pragma once
// The SoE server of an emulated Sercos-profile drive (ETG.1000.6 §5.9,
// docs/ESC_EMULATION.md "SoE server"): IDN parameters per drive number.
//
// What a drive holds: S-0-0011 (class 1 diagnostic, 0), S-0-0015 (telegram
// type, 7: configurable), S-0-0017 (the list of its IDNs) and every IDN the
// ENI's SoE InitCmds address (its value zeros of their length until
// written). Drive 0 always exists, and each drive number the InitCmds use.
//   read:  the value (element 0x40), the name (0x02, as a Sercos string:
//          actual and maximum length, then the characters) or the
//          attribute (0x04); unit, minimum, maximum and default are not kept
//          (errors 0x4001, 0x5001, 0x6001, 0x8001). An answer longer than SM1
//          goes in fragments, the next when the master has read SM1.
//   write: the value only (other elements: read only, 0x2004/0x3004);
//          fragments (incomplete bit) are collected until the last one,
//          which is answered.
// Unknown IDN -> 0x1001, unknown drive -> 0x800A, no element -> 0x800C.

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ecpair/eni/model.hpp"
#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/wire/soe.hpp"

namespace ecpair::sim {

class SoeServer final : public MailboxProtocol {
public:
    struct Idn {
        std::string name;
        std::uint32_t attribute = 0;
        std::vector<std::uint8_t> value;
    };

    // The drives and IDNs of a slave whose ENI entry has `init_cmds`.
    explicit SoeServer(const std::vector<eni::SoeInitCmd>& init_cmds);

    wire::MailboxType type() const override { return wire::MailboxType::SoE; }
    bool serves_in(eni::SlaveState state) const override {
        return state == eni::SlaveState::Preop || state == eni::SlaveState::Safeop || state == eni::SlaveState::Op;
    }
    void on_request(ConstBytes body, MailboxReplies& replies) override;
    void on_reply_read(MailboxReplies& replies) override;
    void end_answer() override { fragments_.clear(); }
    void reset() override;

    // nullptr when the drive does not hold the IDN.
    const Idn* idn(std::uint8_t drive, std::uint16_t idn) const;

private:
    void read(const wire::SoeHeader& request, MailboxReplies& replies);
    void write(const wire::SoeHeader& request, ConstBytes data, MailboxReplies& replies);
    void fail(wire::SoeOpcode answer, const wire::SoeHeader& request, std::uint16_t code, MailboxReplies& replies);

    std::map<std::pair<std::uint8_t, std::uint16_t>, Idn> idns_;
    std::deque<std::vector<std::uint8_t>> fragments_;  // of a read answer, still to send
    std::vector<std::uint8_t> written_;                 // fragments of a write so far
};

}  // namespace ecpair::sim
