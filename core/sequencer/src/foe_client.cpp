// The master's FoE state machine (see the header): every step sends one
// message and waits for the slave's answer to it. Packet sizes follow the
// mailbox areas: what the master writes must fit SM0, what the slave writes
// fits SM1, both after the mailbox header (6) and the FoE header (6).

#include "ecpair/sequencer/foe_client.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/foe.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::size_t kFoeOverhead = wire::MailboxHeader::kSize + wire::kFoeHeaderSize;

std::string describe(const wire::FoeMessage& message) {
    return std::visit(
        [](const auto& m) -> std::string {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, wire::FoeReadRequest>) return "a read request";
            else if constexpr (std::is_same_v<T, wire::FoeWriteRequest>) return "a write request";
            else if constexpr (std::is_same_v<T, wire::FoeData>) return fmt::format("DATA packet {}", m.packet);
            else if constexpr (std::is_same_v<T, wire::FoeAck>) return fmt::format("ACK of packet {}", m.packet);
            else if constexpr (std::is_same_v<T, wire::FoeError>) return "an error";
            else return "BUSY";
        },
        message);
}

}  // namespace

struct FoeClient::Transfer {
    std::string what;  // "FoE read 'app.bin'"
    std::chrono::milliseconds timeout;
    std::stop_token stop;
};

Expected<std::vector<std::uint8_t>, ProtocolError> FoeClient::read(const std::string& file, std::uint32_t password,
                                                                   std::size_t max_size,
                                                                   std::chrono::milliseconds timeout,
                                                                   std::stop_token stop) {
    const Transfer transfer{fmt::format("FoE read '{}'", file), timeout, stop};
    const std::size_t recv_length = transport_.channel().recv.length;
    if (recv_length <= kFoeOverhead) {
        return unexpected(protocol_error(ProtocolFailure::TooLong, transfer.what,
                                         fmt::format("the slave's {}-byte mailbox is too small", recv_length)));
    }
    const std::size_t full_packet = recv_length - kFoeOverhead;
    std::vector<std::uint8_t> file_data;
    wire::FoeMessage next = wire::FoeReadRequest{password, file};
    for (std::uint32_t expected = 1;; ++expected) {
        auto answer = exchange(transfer, next);
        if (!answer) return unexpected(std::move(answer).error());
        const auto* data = std::get_if<wire::FoeData>(&*answer);
        if (data == nullptr) {
            return unexpected(protocol_error(ProtocolFailure::Malformed, transfer.what,
                                             fmt::format("{} instead of DATA packet {}", describe(*answer), expected)));
        }
        if (data->packet != expected) {
            return unexpected(abandon(transfer, wire::foe_error::kPacketNumberWrong,
                                      fmt::format("DATA packet {} instead of {}", data->packet, expected)));
        }
        if (file_data.size() + data->data.size() > max_size) {
            auto error = abandon(transfer, wire::foe_error::kDiskFull,
                                 fmt::format("the file grows past the {}-byte limit", max_size));
            error.failure = ProtocolFailure::TooLong;
            return unexpected(std::move(error));
        }
        file_data.insert(file_data.end(), data->data.begin(), data->data.end());
        const bool last = data->data.size() < full_packet;
        if (last) {
            // The last ACK has no answer.
            const auto deadline = clock_.now() + timeout;
            const auto ack = wire::encode_foe(wire::FoeAck{expected});
            if (auto sent = transport_.send_message(wire::MailboxType::FoE, ack, deadline, stop); !sent) {
                return unexpected(protocol_error_from(sent.error(), transfer.what));
            }
            return file_data;
        }
        next = wire::FoeAck{expected};
    }
}

Expected<void, ProtocolError> FoeClient::write(const std::string& file, std::uint32_t password, ConstBytes data,
                                               std::chrono::milliseconds timeout, std::stop_token stop) {
    const Transfer transfer{fmt::format("FoE write '{}'", file), timeout, stop};
    const std::size_t send_length = transport_.channel().send.length;
    if (send_length <= kFoeOverhead || kFoeOverhead + file.size() > send_length) {
        return unexpected(protocol_error(ProtocolFailure::TooLong, transfer.what,
                                         fmt::format("the file name does not fit the slave's {}-byte mailbox",
                                                     send_length)));
    }
    const std::size_t full_packet = send_length - kFoeOverhead;
    wire::FoeMessage next = wire::FoeWriteRequest{password, file};
    std::size_t offset = 0;
    for (std::uint32_t packet = 0;; ++packet) {
        auto answer = exchange(transfer, next);
        if (!answer) return unexpected(std::move(answer).error());
        const auto* ack = std::get_if<wire::FoeAck>(&*answer);
        if (ack == nullptr) {
            return unexpected(protocol_error(ProtocolFailure::Malformed, transfer.what,
                                             fmt::format("{} instead of the ACK of packet {}", describe(*answer), packet)));
        }
        if (ack->packet != packet) {
            return unexpected(abandon(transfer, wire::foe_error::kPacketNumberWrong,
                                      fmt::format("ACK of packet {} instead of {}", ack->packet, packet)));
        }
        // Done when the packet just acknowledged was shorter than a full one.
        if (packet > 0 && std::get<wire::FoeData>(next).data.size() < full_packet) return {};
        const std::size_t length = std::min(full_packet, data.size() - offset);
        next = wire::FoeData{packet + 1, {data.begin() + static_cast<std::ptrdiff_t>(offset),
                                          data.begin() + static_cast<std::ptrdiff_t>(offset + length)}};
        offset += length;
    }
}

Expected<wire::FoeMessage, ProtocolError> FoeClient::exchange(const Transfer& transfer, const wire::FoeMessage& message) {
    const auto bytes = wire::encode_foe(message);
    const auto busy_until = clock_.now() + transfer.timeout;
    for (;;) {
        const auto deadline = clock_.now() + transfer.timeout;
        if (auto sent = transport_.send_message(wire::MailboxType::FoE, bytes, deadline, transfer.stop); !sent) {
            return unexpected(protocol_error_from(sent.error(), transfer.what));
        }
        auto answer = receive(transfer, deadline);
        if (!answer) return unexpected(std::move(answer).error());
        if (const auto* error = std::get_if<wire::FoeError>(&*answer)) {
            auto e = protocol_error(ProtocolFailure::Refused, transfer.what,
                                    fmt::format("the slave answered error 0x{:04x} {}{}", error->code,
                                                wire::foe_error_text(error->code),
                                                error->text.empty() ? std::string() : " (" + error->text + ")"));
            e.code = error->code;
            return unexpected(std::move(e));
        }
        const auto* busy = std::get_if<wire::FoeBusy>(&*answer);
        if (busy == nullptr) return answer;
        if (clock_.now() >= busy_until) {
            return unexpected(protocol_error(ProtocolFailure::Timeout, transfer.what,
                                             fmt::format("the slave stayed busy for {} ms ({} of {})",
                                                         transfer.timeout.count(), busy->done, busy->entire)));
        }
        logger("sequencer")->debug("station {}: {}: busy ({} of {}), {} again", transport_.channel().station,
                                   transfer.what, busy->done, busy->entire, describe(message));
        clock_.sleep_for(kBusyRetryDelay, transfer.stop);
        if (transfer.stop.stop_requested()) return unexpected(protocol_error(ProtocolFailure::Stopped, transfer.what, "stopped"));
    }
}

Expected<wire::FoeMessage, ProtocolError> FoeClient::receive(const Transfer& transfer, Clock::time_point deadline) {
    auto body = transport_.receive_message(wire::MailboxType::FoE, deadline, transfer.stop);
    if (!body) return unexpected(protocol_error_from(body.error(), transfer.what));
    auto message = wire::decode_foe(*body);
    if (!message) {
        return unexpected(protocol_error(ProtocolFailure::Malformed, transfer.what,
                                         fmt::format("an FoE answer of {} bytes that does not decode", body->size())));
    }
    if (std::holds_alternative<wire::FoeReadRequest>(*message) || std::holds_alternative<wire::FoeWriteRequest>(*message)) {
        return unexpected(protocol_error(ProtocolFailure::Malformed, transfer.what,
                                         fmt::format("the slave sent {}", describe(*message))));
    }
    return std::move(*message);
}

ProtocolError FoeClient::abandon(const Transfer& transfer, std::uint32_t code, const std::string& why) {
    const auto deadline = clock_.now() + transfer.timeout;
    const auto error = wire::encode_foe(wire::FoeError{code, why});
    if (auto sent = transport_.send_message(wire::MailboxType::FoE, error, deadline, transfer.stop); !sent) {
        logger("sequencer")->debug("station {}: {}: the error could not be sent: {}", transport_.channel().station,
                                   transfer.what, sent.error().message);
    }
    return protocol_error(ProtocolFailure::Malformed, transfer.what, why);
}

}  // namespace ecpair::sequencer
