#pragma once
// The EoE client (ETG.1000.6 §5.7), as far as a master configures a slave's
// IP stack: "set IP parameter" (frame type 2) and its response (type 3),
// whose result code must be success. Ethernet fragments the slave sends
// meanwhile (type 0: its own traffic; ecpair tunnels none) are dropped.

#include <chrono>
#include <cstdint>
#include <stop_token>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/sequencer/protocol_error.hpp"
#include "ecpair/wire/eoe.hpp"

namespace ecpair::sequencer {

class EoeClient {
public:
    EoeClient(MailboxTransport& transport, Clock& clock) : transport_(transport), clock_(clock) {}

    Expected<void, ProtocolError> set_ip_parameters(const wire::EoeIpParameters& parameters, std::uint8_t port,
                                                    std::chrono::milliseconds timeout, std::stop_token stop = {});
    // The request's data as an ENI's EoE InitCmd carries it (the IP parameters, after the EoE header).
    Expected<void, ProtocolError> set_ip_parameters(ConstBytes request_data, std::uint8_t port,
                                                    std::chrono::milliseconds timeout, std::stop_token stop = {});
    Expected<wire::EoeIpParameters, ProtocolError> get_ip_parameters(std::uint8_t port,
                                                                     std::chrono::milliseconds timeout,
                                                                     std::stop_token stop = {});

private:
    // Sends a request of `type` with `data`, returns the data of the response of `answer` type.
    Expected<std::vector<std::uint8_t>, ProtocolError> transact(const std::string& what, wire::EoeFrameType type,
                                                                wire::EoeFrameType answer, std::uint8_t port,
                                                                ConstBytes data, std::chrono::milliseconds timeout,
                                                                std::stop_token stop);

    MailboxTransport& transport_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
