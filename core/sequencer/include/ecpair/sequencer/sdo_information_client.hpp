#pragma once
// The CoE SDO Information client (ETG.1000.6 §5.6.3): how a master walks a
// slave's object dictionary over one slave's mailbox.
//   object_list:        Get OD List of a list type -> the object indices;
//   object_description: Get Object Description -> data type, max subindex,
//                       object code, name;
//   entry_description:  Get Entry Description -> data type, bit length,
//                       access rights, name.
// A response longer than one mailbox comes in fragments (the incomplete bit,
// fragments left counting down); their service data joined is the response.
// An SDO Info Error answer ends the request with its SDO abort code. Errors
// are SdoErrors, named "SDO Information ..." with the object.

#include <chrono>
#include <cstdint>
#include <stop_token>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/sequencer/sdo_client.hpp"
#include "ecpair/wire/sdo_information.hpp"

namespace ecpair::sequencer {

class SdoInformationClient {
public:
    SdoInformationClient(MailboxTransport& transport, Clock& clock) : transport_(transport), clock_(clock) {}

    Expected<std::vector<std::uint16_t>, SdoError> object_list(wire::OdListType list,
                                                               std::chrono::milliseconds timeout,
                                                               std::stop_token stop = {});
    Expected<wire::ObjectDescription, SdoError> object_description(std::uint16_t index,
                                                                   std::chrono::milliseconds timeout,
                                                                   std::stop_token stop = {});
    Expected<wire::EntryDescription, SdoError> entry_description(std::uint16_t index, std::uint8_t subindex,
                                                                 std::chrono::milliseconds timeout,
                                                                 std::stop_token stop = {});

private:
    struct Query;
    // Sends the request and returns the joined service data of the response with `answer`'s opcode.
    Expected<std::vector<std::uint8_t>, SdoError> transact(const Query& query, const wire::SdoInfoRequest& request,
                                                           wire::SdoInfoOpcode answer);

    MailboxTransport& transport_;
    Clock& clock_;
};

}  // namespace ecpair::sequencer
