#pragma once
// The SDO part of the CoE server: one decoded request in, one reply out,
// with the state of a segmented transfer kept in between (ETG.1000.6
// §5.6.2). The transfer state machine:
//
//   Idle              --download initiate, more data announced---> SegmentedDownload
//   Idle              --upload initiate, value longer than a reply-> SegmentedUpload
//   SegmentedDownload --last segment, error, abort, new initiate--> Idle
//   SegmentedUpload   --last segment, error, abort, new initiate--> Idle
//
// A segment in the wrong state is an unknown command (0x05040001), a
// segment with the wrong toggle bit ends the transfer with 0x05030000.
// Uploads answer expedited up to 4 bytes, normal when the value fits one
// reply, segmented otherwise. Every transition is logged.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "ecpair/sim/coe_server.hpp"
#include "ecpair/sim/object_dictionary.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sim {

enum class SdoTransferState : std::uint8_t { Idle, SegmentedDownload, SegmentedUpload };
std::string_view to_string(SdoTransferState state);

class SdoServer {
public:
    // `reply_capacity`: the bytes an SDO reply may take (SM1 less the
    // mailbox and CoE headers); at least SdoMessage::kHeaderSize.
    SdoServer(ObjectDictionary& dictionary, CoeSlaveContext& slave, std::size_t reply_capacity);

    // The reply to `request`; nullopt when there is none (the master aborted).
    std::optional<wire::SdoMessage> handle(const wire::SdoMessage& request);
    // The mailbox stopped: a transfer in progress is forgotten.
    void reset();

private:
    void enter(SdoTransferState next, std::string_view why);
    wire::SdoMessage initiate_download(const wire::SdoMessage& request);
    wire::SdoMessage download_segment(const wire::SdoMessage& request);
    wire::SdoMessage initiate_upload(const wire::SdoMessage& request);
    wire::SdoMessage upload_segment(const wire::SdoMessage& request);
    // Writes into the dictionary and reports a changed PDO configuration.
    Expected<void, SdoAbortCode> store(ConstBytes data);
    // Ends the transfer of address_ with an abort.
    wire::SdoMessage abort(SdoAbortCode code);
    wire::SdoMessage response(wire::SdoCommand command) const;

    ObjectDictionary& dictionary_;
    CoeSlaveContext& slave_;
    std::size_t reply_capacity_;
    SdoTransferState state_ = SdoTransferState::Idle;
    SdoAddress address_;               // of the request being served
    std::vector<std::uint8_t> data_;   // download: received so far; upload: the whole value
    std::size_t announced_size_ = 0;   // download: the complete size of the initiate request
    std::size_t uploaded_ = 0;         // upload: bytes sent so far
    bool toggle_ = false;              // the toggle bit the next segment must carry
};

}  // namespace ecpair::sim
