// SM0 writes and SM1 reads of whole mailbox buffers (see the header). Every
// loop waits one poll interval between two datagrams and ends at its
// deadline or on a stop request.

#include "ecpair/sequencer/mailbox_transport.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint16_t kSm1StatusRegister = wire::reg::kSmBase + wire::reg::kSmSize * 1 + 5;  // 0x080D
constexpr std::uint8_t kMailboxFull = 0x08;
constexpr std::chrono::milliseconds kDatagramTimeout{100};

bus::DatagramRequest fprd(std::uint16_t station, std::uint16_t ado, std::size_t length) {
    bus::DatagramRequest request;
    request.command = wire::Command::Fprd;
    request.address = wire::DatagramHeader::physical(station, ado);
    request.data.assign(length, 0);
    request.timeout = kDatagramTimeout;
    return request;
}

MailboxError stopped() { return MailboxError{MailboxFailure::Stopped, std::nullopt, "stopped"}; }

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
    return unexpected(MailboxError{MailboxFailure::Bus, code, reply.error().message});
}

Expected<void, MailboxError> MailboxTransport::send(ConstBytes message, Clock::time_point deadline,
                                                    std::stop_token stop) {
    if (message.size() > channel_.send.length) {
        return unexpected(MailboxError{MailboxFailure::TooLong, std::nullopt,
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
    return unexpected(MailboxError{MailboxFailure::Timeout, std::nullopt,
                                   fmt::format("mailbox of station {} stays full (SM0 write not accepted)",
                                               channel_.station)});
}

Expected<bool, MailboxError> MailboxTransport::sm1_full() {
    auto status = poll(fprd(channel_.station, kSm1StatusRegister, 1));
    if (!status) return unexpected(std::move(status).error());
    return *status && (*status)->wkc == 1 && !(*status)->data.empty() && ((*status)->data[0] & kMailboxFull) != 0;
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
    return unexpected(MailboxError{MailboxFailure::Timeout, std::nullopt,
                                   fmt::format("no mailbox reply from station {}", channel_.station)});
}

Expected<void, MailboxError> MailboxTransport::discard_stale_reply(std::stop_token stop) {
    if (stop.stop_requested()) return unexpected(stopped());
    auto full = sm1_full();
    if (!full) return unexpected(std::move(full).error());
    if (!*full) return {};
    auto reply = poll(fprd(channel_.station, channel_.recv.start, channel_.recv.length));
    if (!reply) return unexpected(std::move(reply).error());
    logger("sequencer")->info("station {}: dropped a stale mailbox reply", channel_.station);
    return {};
}

}  // namespace ecpair::sequencer
