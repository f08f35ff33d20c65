// SDO transfers as a sequence of request/response pairs over the mailbox
// transport. Each pair: write the request into SM0 (send_message reads a
// stale reply away first), read SM1 until a CoE message arrives
// (emergencies and other protocols are the transport's), then check that it
// answers this request (command, object, toggle bit). Sizes: a message is
// mailbox header (6) + CoE header (2) + the SDO part, and must fit into
// SM0's Send Length.

#include "ecpair/sequencer/sdo_client.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::size_t kFrameOverhead = wire::MailboxHeader::kSize + wire::CoeHeader::kSize;
constexpr std::size_t kExpeditedMax = 4;

}  // namespace

struct SdoClient::Transfer {
    std::uint16_t index;
    std::uint8_t subindex;
    std::string_view what;  // "download" / "upload"
    std::chrono::milliseconds timeout;
    std::stop_token stop;

    SdoError error(SdoFailure failure, const std::string& detail) const {
        SdoError e;
        e.failure = failure;
        e.index = index;
        e.subindex = subindex;
        e.message = fmt::format("SDO 0x{:04x}:{:02x} {}: {}", index, subindex, what, detail);
        return e;
    }
};

SdoError sdo_error_from(const MailboxError& e, std::uint16_t index, std::uint8_t subindex, const std::string& prefix) {
    SdoError error;
    switch (e.failure) {
        case MailboxFailure::Timeout: error.failure = SdoFailure::Timeout; break;
        case MailboxFailure::TooLong: error.failure = SdoFailure::TooLong; break;
        case MailboxFailure::Bus: error.failure = SdoFailure::Bus; break;
        case MailboxFailure::Stopped: error.failure = SdoFailure::Stopped; break;
        case MailboxFailure::ErrorReply: error.failure = SdoFailure::MailboxError; break;
        case MailboxFailure::Malformed: error.failure = SdoFailure::Protocol; break;
    }
    error.index = index;
    error.subindex = subindex;
    error.mailbox_error = e.error_reply;
    error.bus_error = e.bus_error;
    error.message = prefix + ": " + e.message;
    return error;
}

std::string_view to_string(SdoFailure failure) {
    switch (failure) {
        case SdoFailure::Abort: return "aborted";
        case SdoFailure::MailboxError: return "mailbox error";
        case SdoFailure::Timeout: return "timeout";
        case SdoFailure::Protocol: return "protocol error";
        case SdoFailure::TooLong: return "too long";
        case SdoFailure::Bus: return "bus refused";
        case SdoFailure::Stopped: return "stopped";
    }
    return "?";
}

SdoClient::SdoClient(MailboxTransport& transport, Clock& clock) : transport_(transport), clock_(clock) {}

Expected<void, SdoError> SdoClient::download(std::uint16_t index, std::uint8_t subindex, ConstBytes data,
                                             bool complete_access, std::chrono::milliseconds timeout,
                                             std::stop_token stop) {
    const Transfer transfer{index, subindex, "download", timeout, stop};
    const std::size_t send_length = transport_.channel().send.length;
    if (send_length < kFrameOverhead + wire::SdoMessage::kHeaderSize) {
        return unexpected(transfer.error(SdoFailure::TooLong, fmt::format("mailbox of {} bytes is too small", send_length)));
    }

    wire::SdoMessage initiate;
    initiate.command = wire::SdoCommand::Download;
    initiate.index = index;
    initiate.subindex = subindex;
    initiate.complete_access = complete_access;
    initiate.expedited = !complete_access && !data.empty() && data.size() <= kExpeditedMax;
    initiate.complete_size = static_cast<std::uint32_t>(data.size());
    const std::size_t first_part =
        initiate.expedited ? data.size()
                           : std::min(data.size(), send_length - kFrameOverhead - wire::SdoMessage::kHeaderSize);
    initiate.data.assign(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(first_part));

    auto response = transact(transfer, initiate);
    if (!response) return unexpected(std::move(response).error());
    if (response->command != wire::SdoCommand::Download || response->index != index ||
        response->subindex != subindex) {
        return unexpected(transfer.error(SdoFailure::Protocol, "the answer is not a download response for this object"));
    }

    // What did not fit follows in segments, the toggle bit alternating from 0.
    const std::size_t segment_capacity = send_length - kFrameOverhead - wire::SdoMessage::kSegmentHeader;
    bool toggle = false;
    for (std::size_t offset = first_part; offset < data.size(); toggle = !toggle) {
        const std::size_t length = std::min(segment_capacity, data.size() - offset);
        wire::SdoMessage segment;
        segment.command = wire::SdoCommand::DownloadSegment;
        segment.toggle = toggle;
        segment.last_segment = offset + length == data.size();
        segment.data.assign(data.begin() + static_cast<std::ptrdiff_t>(offset),
                            data.begin() + static_cast<std::ptrdiff_t>(offset + length));
        auto answer = transact(transfer, segment);
        if (!answer) return unexpected(std::move(answer).error());
        if (answer->command != wire::SdoCommand::DownloadSegment || answer->toggle != toggle) {
            return unexpected(transfer.error(SdoFailure::Protocol,
                                             fmt::format("segment at byte {}: the answer is not a download segment "
                                                         "response with toggle {}", offset, toggle ? 1 : 0)));
        }
        offset += length;
    }
    return {};
}

Expected<std::vector<std::uint8_t>, SdoError> SdoClient::upload(std::uint16_t index, std::uint8_t subindex,
                                                                bool complete_access,
                                                                std::chrono::milliseconds timeout,
                                                                std::stop_token stop) {
    const Transfer transfer{index, subindex, "upload", timeout, stop};
    wire::SdoMessage initiate;
    initiate.command = wire::SdoCommand::Upload;
    initiate.index = index;
    initiate.subindex = subindex;
    initiate.complete_access = complete_access;
    auto response = transact(transfer, initiate);
    if (!response) return unexpected(std::move(response).error());
    if (response->command != wire::SdoCommand::Upload || response->index != index ||
        response->subindex != subindex) {
        return unexpected(transfer.error(SdoFailure::Protocol, "the answer is not an upload response for this object"));
    }
    if (response->expedited) return std::move(response->data);

    std::vector<std::uint8_t> data = std::move(response->data);
    const std::size_t total = response->complete_size;
    // Every segment carries at least one byte, so `total` segments is the most an honest slave sends.
    bool toggle = false;
    for (std::size_t segments = 0; data.size() < total; ++segments, toggle = !toggle) {
        if (segments > total) {
            return unexpected(transfer.error(SdoFailure::Protocol, "the slave keeps sending empty segments"));
        }
        wire::SdoMessage request;
        request.command = wire::SdoCommand::UploadSegment;
        request.toggle = toggle;
        auto segment = transact(transfer, request);
        if (!segment) return unexpected(std::move(segment).error());
        if (segment->command != wire::SdoCommand::UploadSegment || segment->toggle != toggle) {
            return unexpected(transfer.error(SdoFailure::Protocol,
                                             fmt::format("after byte {}: the answer is not an upload segment with "
                                                         "toggle {}", data.size(), toggle ? 1 : 0)));
        }
        data.insert(data.end(), segment->data.begin(), segment->data.end());
        if (segment->last_segment) break;
    }
    if (data.size() != total) {
        return unexpected(transfer.error(SdoFailure::Protocol,
                                         fmt::format("{} bytes announced, {} received", total, data.size())));
    }
    return data;
}

Expected<wire::SdoMessage, SdoError> SdoClient::transact(const Transfer& transfer, const wire::SdoMessage& request) {
    const auto from_mailbox = [&transfer](const MailboxError& e) {
        return sdo_error_from(e, transfer.index, transfer.subindex,
                              fmt::format("SDO 0x{:04x}:{:02x} {}", transfer.index, transfer.subindex, transfer.what));
    };
    std::vector<std::uint8_t> message(wire::CoeHeader::kSize + request.encoded_size(), 0);
    wire::CoeHeader{0, wire::CoeService::SdoRequest}.encode(message);
    request.encode(Bytes(message).subspan(wire::CoeHeader::kSize));

    const auto deadline = clock_.now() + transfer.timeout;
    if (auto sent = transport_.send_message(wire::MailboxType::CoE, message, deadline, transfer.stop); !sent) {
        return unexpected(from_mailbox(sent.error()));
    }
    for (;;) {
        auto body = transport_.receive_message(wire::MailboxType::CoE, deadline, transfer.stop);
        if (!body) return unexpected(from_mailbox(body.error()));
        auto reply = decode_reply(transfer, *body);
        if (!reply) return unexpected(std::move(reply).error());
        if (*reply) return std::move(**reply);
    }
}

// nullopt: a CoE message that is no answer to us (SDO Information, a PDO): wait for the next one.
Expected<std::optional<wire::SdoMessage>, SdoError> SdoClient::decode_reply(const Transfer& transfer, ConstBytes body) {
    const auto coe = wire::CoeHeader::decode(body);
    if (!coe) return unexpected(transfer.error(SdoFailure::Protocol, "CoE header missing in the reply"));
    if (coe->service == wire::CoeService::SdoInformation || coe->service == wire::CoeService::TxPdo ||
        coe->service == wire::CoeService::RxPdo) {
        logger("sequencer")->debug("station {}: skipped a CoE message of service {} during an SDO {}",
                                   transport_.channel().station, static_cast<unsigned>(coe->service), transfer.what);
        return std::optional<wire::SdoMessage>();
    }
    // Slaves send an abort with either SDO service (SOES and others use the request service 2).
    if (coe->service != wire::CoeService::SdoResponse && coe->service != wire::CoeService::SdoRequest) {
        return unexpected(transfer.error(SdoFailure::Protocol,
                                         fmt::format("CoE service {} instead of an SDO response",
                                                     static_cast<unsigned>(coe->service))));
    }
    auto sdo = wire::SdoMessage::decode(body.subspan(wire::CoeHeader::kSize), true);
    if (sdo && coe->service == wire::CoeService::SdoRequest && sdo->command != wire::SdoCommand::Abort) {
        return unexpected(transfer.error(SdoFailure::Protocol, "CoE service 2 (SDO request) in a reply that is no abort"));
    }
    if (!sdo) return unexpected(transfer.error(SdoFailure::Protocol, "malformed SDO response"));
    if (sdo->command == wire::SdoCommand::Abort) {
        auto error = transfer.error(SdoFailure::Abort, fmt::format("aborted: 0x{:08x} {}", sdo->complete_size,
                                                                   wire::sdo_abort_text(sdo->complete_size)));
        error.abort_code = sdo->complete_size;
        return unexpected(std::move(error));
    }
    return std::optional<wire::SdoMessage>(std::move(*sdo));
}

}  // namespace ecpair::sequencer
