// SoE read and write with their fragments (see the header). The answer must
// be of the opcode expected for the drive asked; the IDN of the last
// fragment must be the one asked.

#include "ecpair/sequencer/soe_client.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecpair::sequencer {
namespace {

constexpr std::size_t kSoeOverhead = wire::MailboxHeader::kSize + wire::SoeHeader::kSize;

std::vector<std::uint8_t> message(const wire::SoeHeader& header, ConstBytes data) {
    std::vector<std::uint8_t> out(wire::SoeHeader::kSize + data.size());
    header.encode(out);
    std::copy(data.begin(), data.end(), out.begin() + wire::SoeHeader::kSize);
    return out;
}

}  // namespace

struct SoeClient::Request {
    std::string what;  // "SoE read S-0-0015 of drive 0"
    wire::SoeOpcode answer;
    std::uint8_t drive;
    std::uint16_t idn;
    std::chrono::milliseconds timeout;
    std::stop_token stop;
};

Expected<std::vector<std::uint8_t>, ProtocolError> SoeClient::read(std::uint8_t drive, std::uint16_t idn,
                                                                   std::uint8_t elements,
                                                                   std::chrono::milliseconds timeout,
                                                                   std::stop_token stop) {
    const Request request{fmt::format("SoE read {} of drive {}", wire::idn_text(idn), drive),
                          wire::SoeOpcode::ReadResponse, drive, idn, timeout, stop};
    wire::SoeHeader header;
    header.opcode = wire::SoeOpcode::ReadRequest;
    header.drive = drive;
    header.elements = elements;
    header.idn_or_fragments = idn;
    auto deadline = clock_.now() + timeout;
    if (auto sent = transport_.send_message(wire::MailboxType::SoE, message(header, {}), deadline, stop); !sent) {
        return unexpected(protocol_error_from(sent.error(), request.what));
    }
    std::vector<std::uint8_t> value;
    for (;;) {
        auto answer = receive(request, deadline);
        if (!answer) return unexpected(std::move(answer).error());
        auto& [h, data] = *answer;
        value.insert(value.end(), data.begin(), data.end());
        if (!h.incomplete) {
            if (h.idn_or_fragments != idn) {
                return unexpected(protocol_error(ProtocolFailure::Malformed, request.what,
                                                 fmt::format("the answer is for {}", wire::idn_text(h.idn_or_fragments))));
            }
            return value;
        }
        deadline = clock_.now() + timeout;
    }
}

Expected<void, ProtocolError> SoeClient::write(std::uint8_t drive, std::uint16_t idn, std::uint8_t elements,
                                               ConstBytes data, std::chrono::milliseconds timeout,
                                               std::stop_token stop) {
    const Request request{fmt::format("SoE write {} of drive {}", wire::idn_text(idn), drive),
                          wire::SoeOpcode::WriteResponse, drive, idn, timeout, stop};
    const std::size_t send_length = transport_.channel().send.length;
    if (send_length <= kSoeOverhead) {
        return unexpected(protocol_error(ProtocolFailure::TooLong, request.what,
                                         fmt::format("the slave's {}-byte mailbox is too small", send_length)));
    }
    const std::size_t capacity = send_length - kSoeOverhead;
    const std::size_t fragments = data.empty() ? 1 : (data.size() + capacity - 1) / capacity;
    if (fragments > 0x10000) {
        return unexpected(protocol_error(ProtocolFailure::TooLong, request.what,
                                         fmt::format("{} bytes need more fragments than SoE counts", data.size())));
    }
    for (std::size_t i = 0; i < fragments; ++i) {
        const std::size_t offset = i * capacity;
        const std::size_t length = std::min(capacity, data.size() - offset);
        wire::SoeHeader header;
        header.opcode = wire::SoeOpcode::WriteRequest;
        header.drive = drive;
        header.elements = elements;
        header.incomplete = i + 1 < fragments;
        header.idn_or_fragments = header.incomplete ? static_cast<std::uint16_t>(fragments - 1 - i) : idn;
        const auto deadline = clock_.now() + timeout;
        if (auto sent = transport_.send_message(wire::MailboxType::SoE, message(header, data.subspan(offset, length)),
                                                deadline, stop);
            !sent) {
            return unexpected(protocol_error_from(sent.error(), request.what));
        }
    }
    auto answer = receive(request, clock_.now() + timeout);
    if (!answer) return unexpected(std::move(answer).error());
    if (answer->first.idn_or_fragments != idn) {
        return unexpected(protocol_error(ProtocolFailure::Malformed, request.what,
                                         fmt::format("the answer is for {}", wire::idn_text(answer->first.idn_or_fragments))));
    }
    return {};
}

Expected<std::pair<wire::SoeHeader, std::vector<std::uint8_t>>, ProtocolError> SoeClient::receive(
    const Request& request, Clock::time_point deadline) {
    for (;;) {
        auto body = transport_.receive_message(wire::MailboxType::SoE, deadline, request.stop);
        if (!body) return unexpected(protocol_error_from(body.error(), request.what));
        const auto header = wire::SoeHeader::decode(*body);
        if (!header) return unexpected(protocol_error(ProtocolFailure::Malformed, request.what, "SoE header missing"));
        // Notifications and slave info (the drive's own messages) answer nothing.
        if (header->opcode == wire::SoeOpcode::Notification || header->opcode == wire::SoeOpcode::SlaveInfo) continue;
        std::vector<std::uint8_t> data(body->begin() + wire::SoeHeader::kSize, body->end());
        if (header->opcode != request.answer || header->drive != request.drive) {
            return unexpected(protocol_error(ProtocolFailure::Malformed, request.what,
                                             fmt::format("opcode {} of drive {} instead of opcode {} of drive {}",
                                                         static_cast<unsigned>(header->opcode), header->drive,
                                                         static_cast<unsigned>(request.answer), request.drive)));
        }
        if (header->error) {
            // The error code is the last word of the message (SOEM reads it there too).
            const std::uint16_t code = data.size() >= 2 ? load_le<std::uint16_t>(data, data.size() - 2) : 0;
            auto e = protocol_error(ProtocolFailure::Refused, request.what,
                                    fmt::format("the drive answered error 0x{:04x} {}", code, wire::soe_error_text(code)));
            e.code = code;
            return unexpected(std::move(e));
        }
        return std::pair{*header, std::move(data)};
    }
}

}  // namespace ecpair::sequencer
