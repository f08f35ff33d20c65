#pragma once
// The EoE server of an emulated slave (ETG.1000.6 §5.7), as far as a master
// configures the slave's IP stack (docs/ESC_EMULATION.md "EoE server"):
//   set IP parameter request (type 2): the parameters included are taken
//     over (the rest stays) and answered with result 0 (success); data that
//     does not decode is answered 0x0001 (unspecified error);
//   get IP parameter request (type 6): answered with the parameters held;
//   address filter requests (4, 8): 0x0401 (no filter support);
//   Ethernet fragments (type 0): dropped (the slave has no network behind it);
//   anything else (responses, unknown types): dropped.
// EoE runs in PREOP, SAFEOP and OP.

#include <cstdint>

#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/wire/eoe.hpp"

namespace ecpair::sim {

class EoeServer final : public MailboxProtocol {
public:
    wire::MailboxType type() const override { return wire::MailboxType::EoE; }
    bool serves_in(eni::SlaveState state) const override {
        return state == eni::SlaveState::Preop || state == eni::SlaveState::Safeop || state == eni::SlaveState::Op;
    }
    void on_request(ConstBytes body, MailboxReplies& replies) override;

    // What the master set (nothing before a set request).
    const wire::EoeIpParameters& ip_parameters() const { return parameters_; }

private:
    void respond(wire::EoeFrameType type, std::uint8_t port, std::uint16_t result, ConstBytes data,
                 MailboxReplies& replies);

    wire::EoeIpParameters parameters_;
};

}  // namespace ecpair::sim
