// SDO transfers as a sequence of request/response pairs over the mailbox
// transport. Each pair: drop a stale reply, write the request into SM0,
// read SM1 until an SDO response arrives (emergencies and other protocols
// are skipped), then check that it answers this request (command, object,
// toggle bit). Sizes: a message is mailbox header (6) + CoE header (2) +
// the SDO part, and must fit into SM0's Send Length.

#include "ecpair/sequencer/sdo_client.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"
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

SdoClient::SdoClient(bus::BusAccess& bus, Clock& clock, MailboxChannel channel)
    : transport_(bus, clock, channel), clock_(clock) {}

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
    const auto from_mailbox = [&transfer](MailboxError e) {
        const auto failure = e.failure == MailboxFailure::Timeout   ? SdoFailure::Timeout
                             : e.failure == MailboxFailure::TooLong ? SdoFailure::TooLong
                             : e.failure == MailboxFailure::Bus     ? SdoFailure::Bus
                                                                    : SdoFailure::Stopped;
        auto error = transfer.error(failure, e.message);
        error.bus_error = e.bus_error;
        return error;
    };

    if (auto drained = transport_.discard_stale_reply(transfer.stop); !drained) {
        return unexpected(from_mailbox(std::move(drained).error()));
    }
    const std::size_t sdo_size = request.encoded_size();
    std::vector<std::uint8_t> message(kFrameOverhead + sdo_size, 0);
    wire::MailboxHeader header;
    header.length = static_cast<std::uint16_t>(wire::CoeHeader::kSize + sdo_size);
    header.type = wire::MailboxType::CoE;
    header.counter = transport_.next_counter();
    header.encode(message);
    wire::CoeHeader{0, wire::CoeService::SdoRequest}.encode(Bytes(message).subspan(wire::MailboxHeader::kSize));
    request.encode(Bytes(message).subspan(kFrameOverhead));

    const auto deadline = clock_.now() + transfer.timeout;
    if (auto sent = transport_.send(message, deadline, transfer.stop); !sent) {
        return unexpected(from_mailbox(std::move(sent).error()));
    }
    for (;;) {
        auto buffer = transport_.receive(deadline, transfer.stop);
        if (!buffer) return unexpected(from_mailbox(std::move(buffer).error()));
        auto reply = decode_reply(transfer, *buffer);
        if (!reply) return unexpected(std::move(reply).error());
        if (*reply) return std::move(**reply);
    }
}

// nullopt: a message that is no answer to us (an emergency, another protocol): wait for the next one.
Expected<std::optional<wire::SdoMessage>, SdoError> SdoClient::decode_reply(const Transfer& transfer,
                                                                           ConstBytes buffer) {
    const auto header = wire::MailboxHeader::decode(buffer);
    if (!header) return unexpected(transfer.error(SdoFailure::Protocol, "malformed mailbox header in the reply"));
    const auto body = buffer.subspan(wire::MailboxHeader::kSize, header->length);
    if (header->type == wire::MailboxType::Error) {
        const auto reply = wire::MailboxErrorReply::decode(body);
        const std::uint16_t detail = reply ? reply->detail : 0;
        auto error = transfer.error(SdoFailure::MailboxError,
                                    fmt::format("mailbox error 0x{:04x} ({})", detail, wire::mailbox_error_text(detail)));
        error.mailbox_error = detail;
        return unexpected(std::move(error));
    }
    if (header->type != wire::MailboxType::CoE) {
        logger("sequencer")->debug("station {}: skipped a mailbox message of type {}", transport_.channel().station,
                                   static_cast<unsigned>(header->type));
        return std::optional<wire::SdoMessage>();
    }
    const auto coe = wire::CoeHeader::decode(body);
    if (!coe) return unexpected(transfer.error(SdoFailure::Protocol, "CoE header missing in the reply"));
    if (coe->service == wire::CoeService::Emergency) {
        logger("sequencer")->warn("station {}: CoE emergency {} during {}", transport_.channel().station,
                                  to_hex(body.subspan(wire::CoeHeader::kSize), " "), transfer.what);
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
