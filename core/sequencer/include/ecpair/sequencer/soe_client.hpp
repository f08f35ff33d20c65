#pragma once
// The SoE client (ETG.1000.6 §5.9): IDN elements of a Sercos-profile drive
// over one slave's mailbox.
//   read:  read request (drive, elements, IDN) -> read response(s): an answer
//          longer than the slave's mailbox comes in fragments (incomplete
//          bit, fragments left in place of the IDN) joined here;
//   write: write request(s) -> write response: data longer than SM0 goes in
//          fragments, each written as soon as the slave took the one before,
//          answered once, after the last.
// An answer with the error bit ends the request with the SoE error code.

#include <chrono>
#include <cstdint>
#include <stop_token>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/sequencer/protocol_error.hpp"
#include "ecpair/wire/soe.hpp"

namespace ecpair::sequencer {

class SoeClient {
public:
    SoeClient(MailboxTransport& transport, Clock& clock) : transport_(transport), clock_(clock) {}

    Expected<std::vector<std::uint8_t>, ProtocolError> read(std::uint8_t drive, std::uint16_t idn,
                                                            std::uint8_t elements, std::chrono::milliseconds timeout,
                                                            std::stop_token stop = {});
    Expected<void, ProtocolError> write(std::uint8_t drive, std::uint16_t idn, std::uint8_t elements, ConstBytes data,
                                        std::chrono::milliseconds timeout, std::stop_token stop = {});

private:
    struct Request;
    // The next SoE answer for `request`: its header and data.
    Expected<std::pair<wire::SoeHeader, std::vector<std::uint8_t>>, ProtocolError> receive(const Request& request,
                                                                                           Clock::time_point deadline);

    MailboxTransport& transport_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
