// SM0 writes and SM1 reads of whole mailbox buffers (see the header). Every
// loop waits one poll interval between two datagrams and ends at its
// deadline or on a stop request. Messages are checked here only as far as
// the mailbox header (and, for emergencies, the CoE header) goes; the
// protocol clients decode the rest.

#include "ecpair/sequencer/mailbox_transport.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::chrono::milliseconds kDatagramTimeout{100};

bus::DatagramRequest fprd(std::uint16_t station, std::uint16_t ado, std::size_t length) {
    bus::DatagramRequest request;
    request.command = wire::Command::Fprd;
    request.address = wire::DatagramHeader::physical(station, ado);
    request.data.assign(length, 0);
    request.timeout = kDatagramTimeout;
    return request;
}

MailboxError stopped() { return MailboxError{MailboxFailure::Stopped, std::nullopt, 0, "stopped"}; }

}  // namespace

std::optional<MailboxChannel> mailbox_channel_of(const eni::Slave& slave) {
    MailboxChannel channel;
    channel.station = slave.info.phys_addr;
    if (slave.mailbox && slave.mailbox->send && slave.mailbox->recv) {
        channel.send = *slave.mailbox->send;
        channel.recv = *slave.mailbox->recv;
        return channel;
    }
    const auto area_of = [&slave](eni::SmType type) -> std::optional<eni::MailboxArea> {
        for (const auto& sm : slave.process_data.sync_managers) {
            const auto size = sm.default_size ? sm.default_size : sm.max_size;
            if (sm.type == type && sm.start_address && size && *size > 0) {
                return eni::MailboxArea{*sm.start_address, *size};
            }
        }
        return std::nullopt;
    };
    const auto send = area_of(eni::SmType::MailboxOut);
    const auto recv = area_of(eni::SmType::MailboxIn);
    if (!send || !recv) return std::nullopt;
    channel.send = *send;
    channel.recv = *recv;
    return channel;
}

MailboxTransport::MailboxTransport(bus::BusAccess& bus, Clock& clock, MailboxChannel channel)
    : bus_(bus), clock_(clock), channel_(channel) {}

std::uint8_t MailboxTransport::next_counter() {
    counter_ = wire::next_mailbox_counter(counter_);
    return counter_;
}

void MailboxTransport::continue_after(std::uint8_t last_counter) {
    counter_ = last_counter;
    drain_before_send_ = true;
}

Expected<std::optional<bus::DatagramReply>, MailboxError> MailboxTransport::poll(const bus::DatagramRequest& request) {
    auto reply = bus_.exchange(request);
    if (reply) return std::optional<bus::DatagramReply>(std::move(reply).value());
    const auto code = reply.error().code;
    if (code == bus::BusErrc::Timeout || code == bus::BusErrc::LinkFailure) {
        return std::optional<bus::DatagramReply>();
    }
    return unexpected(MailboxError{MailboxFailure::Bus, code, 0, reply.error().message});
}

Expected<void, MailboxError> MailboxTransport::send(ConstBytes message, Clock::time_point deadline,
                                                    std::stop_token stop) {
    if (message.size() > channel_.send.length) {
        return unexpected(MailboxError{MailboxFailure::TooLong, std::nullopt, 0,
                                       fmt::format("{}-byte message does not fit the {}-byte mailbox of station {}",
                                                   message.size(), channel_.send.length, channel_.station)});
    }
    bus::DatagramRequest request;
    request.command = wire::Command::Fpwr;
    request.address = wire::DatagramHeader::physical(channel_.station, channel_.send.start);
    request.data.assign(channel_.send.length, 0);
    std::copy(message.begin(), message.end(), request.data.begin());
    request.timeout = kDatagramTimeout;
    if (drain_before_send_) {
        if (auto drained = discard_stale_reply(stop); !drained) return drained;
        drain_before_send_ = false;
    }
    for (;;) {
        if (stop.stop_requested()) return unexpected(stopped());
        auto reply = poll(request);
        if (!reply) return unexpected(std::move(reply).error());
        if (*reply && (*reply)->wkc == 1) return {};
        if (clock_.now() >= deadline) break;
        clock_.sleep_for(kPollInterval, stop);
    }
    return unexpected(MailboxError{MailboxFailure::Timeout, std::nullopt, 0,
                                   fmt::format("mailbox of station {} stays full (SM0 write not accepted)",
                                               channel_.station)});
}

Expected<bool, MailboxError> MailboxTransport::sm1_full() {
    auto status = poll(fprd(channel_.station, wire::kSm1StatusRegister, 1));
    if (!status) return unexpected(std::move(status).error());
    return *status && (*status)->wkc == 1 && !(*status)->data.empty() && ((*status)->data[0] & wire::kSmStatusMailboxFull) != 0;
}

Expected<std::vector<std::uint8_t>, MailboxError> MailboxTransport::receive(Clock::time_point deadline,
                                                                            std::stop_token stop) {
    const auto read = fprd(channel_.station, channel_.recv.start, channel_.recv.length);
    for (;;) {
        if (stop.stop_requested()) return unexpected(stopped());
        auto full = sm1_full();
        if (!full) return unexpected(std::move(full).error());
        if (*full) {
            auto reply = poll(read);
            if (!reply) return unexpected(std::move(reply).error());
            if (*reply && (*reply)->wkc == 1) return std::move((*reply)->data);
        }
        if (clock_.now() >= deadline) break;
        clock_.sleep_for(kPollInterval, stop);
    }
    return unexpected(MailboxError{MailboxFailure::Timeout, std::nullopt, 0,
                                   fmt::format("no mailbox reply from station {}", channel_.station)});
}

Expected<void, MailboxError> MailboxTransport::discard_stale_reply(std::stop_token stop) {
    if (stop.stop_requested()) return unexpected(stopped());
    auto full = sm1_full();
    if (!full) return unexpected(std::move(full).error());
    if (!*full) return {};
    auto reply = poll(fprd(channel_.station, channel_.recv.start, channel_.recv.length));
    if (!reply) return unexpected(std::move(reply).error());
    if (*reply && (*reply)->wkc == 1 && take_emergency((*reply)->data)) return {};
    logger("sequencer")->info("station {}: dropped a stale mailbox reply", channel_.station);
    return {};
}

Expected<void, MailboxError> MailboxTransport::send_message(wire::MailboxType type, ConstBytes payload,
                                                            Clock::time_point deadline, std::stop_token stop) {
    if (auto drained = discard_stale_reply(stop); !drained) return drained;
    drain_before_send_ = false;
    std::vector<std::uint8_t> message(wire::MailboxHeader::kSize + payload.size());
    wire::MailboxHeader header;
    header.length = static_cast<std::uint16_t>(payload.size());
    header.type = type;
    header.counter = next_counter();
    header.encode(message);
    std::copy(payload.begin(), payload.end(), message.begin() + wire::MailboxHeader::kSize);
    return send(message, deadline, stop);
}

Expected<std::vector<std::uint8_t>, MailboxError> MailboxTransport::receive_message(wire::MailboxType type,
                                                                                    Clock::time_point deadline,
                                                                                    std::stop_token stop) {
    for (;;) {
        auto buffer = receive(deadline, stop);
        if (!buffer) return unexpected(std::move(buffer).error());
        auto message = take_message(type, *buffer);
        if (!message) return unexpected(std::move(message).error());
        if (*message) return std::move(**message);
    }
}

Expected<std::optional<std::vector<std::uint8_t>>, MailboxError> MailboxTransport::take_message(wire::MailboxType type,
                                                                                               ConstBytes buffer) {
    const auto header = wire::MailboxHeader::decode(buffer);
    if (!header) {
        return unexpected(MailboxError{MailboxFailure::Malformed, std::nullopt, 0,
                                       fmt::format("station {}: a reply whose mailbox header does not fit the "
                                                   "{}-byte mailbox", channel_.station, buffer.size())});
    }
    const auto body = buffer.subspan(wire::MailboxHeader::kSize, header->length);
    if (header->type == wire::MailboxType::Error) {
        const auto reply = wire::MailboxErrorReply::decode(body);
        const std::uint16_t detail = reply ? reply->detail : 0;
        return unexpected(MailboxError{MailboxFailure::ErrorReply, std::nullopt, detail,
                                       fmt::format("mailbox error 0x{:04x} ({})", detail,
                                                   wire::mailbox_error_text(detail))});
    }
    if (take_emergency(buffer)) return std::optional<std::vector<std::uint8_t>>();
    if (header->type != type) {
        logger("sequencer")->debug("station {}: skipped a mailbox message of type {} while waiting for type {}",
                                   channel_.station, static_cast<unsigned>(header->type),
                                   static_cast<unsigned>(type));
        return std::optional<std::vector<std::uint8_t>>();
    }
    return std::optional<std::vector<std::uint8_t>>(std::vector<std::uint8_t>(body.begin(), body.end()));
}

bool MailboxTransport::take_emergency(ConstBytes buffer) {
    const auto header = wire::MailboxHeader::decode(buffer);
    if (!header || header->type != wire::MailboxType::CoE) return false;
    const auto body = buffer.subspan(wire::MailboxHeader::kSize, header->length);
    const auto coe = wire::CoeHeader::decode(body);
    if (!coe || coe->service != wire::CoeService::Emergency) return false;
    const auto emergency = wire::CoeEmergency::decode(body.subspan(wire::CoeHeader::kSize));
    if (!emergency) {
        logger("sequencer")->warn("station {}: a CoE emergency too short to read: {}", channel_.station,
                                  to_hex(body, " "));
        return true;
    }
    if (emergency_handler_) {
        emergency_handler_(*emergency);
    } else {
        logger("sequencer")->warn("station {}: CoE emergency 0x{:04x} ({}), error register 0x{:02x}, data {}",
                                  channel_.station, emergency->error_code,
                                  wire::emergency_error_class(emergency->error_code), emergency->error_register,
                                  to_hex(emergency->data, " "));
    }
    return true;
}

void MailboxTransport::dispatch_unsolicited(ConstBytes buffer) {
    if (take_emergency(buffer)) return;
    logger("sequencer")->debug("station {}: dropped a mailbox message nobody waited for", channel_.station);
}

}  // namespace ecpair::sequencer
