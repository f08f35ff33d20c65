// The slave's FoE state machine (see the header). Every answer is one
// message; an error always returns to Idle.

#include "ecpair/sim/foe_server.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sim {
namespace {

constexpr std::size_t kOverhead = wire::MailboxHeader::kSize + wire::kFoeHeaderSize;

std::size_t packet_of(std::size_t mailbox_size) { return mailbox_size > kOverhead ? mailbox_size - kOverhead : 0; }

}  // namespace

FoeServer::FoeServer(std::size_t mailbox_out_size, std::size_t mailbox_in_size, std::size_t room)
    : out_packet_(packet_of(mailbox_out_size)), in_packet_(packet_of(mailbox_in_size)), room_(room) {}

void FoeServer::reset() {
    state_ = State::Idle;
    file_.clear();
    data_.clear();
    offset_ = 0;
    in_flight_ = 0;
    packet_ = 0;
}

std::size_t FoeServer::stored_bytes() const {
    std::size_t total = 0;
    for (const auto& [name, data] : files_) total += data.size();
    return total;
}

void FoeServer::fail(std::uint32_t code, const std::string& text, MailboxReplies& replies) {
    logger("esc")->debug("FoE: error 0x{:04x} ({}): {}", code, wire::foe_error_text(code), text);
    reset();
    replies.reply(wire::encode_foe(wire::FoeError{code, text}));
}

void FoeServer::on_request(ConstBytes body, MailboxReplies& replies) {
    const auto message = wire::decode_foe(body);
    if (!message) return fail(wire::foe_error::kIllegal, "not an FoE message", replies);
    std::visit(
        [&](const auto& m) {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, wire::FoeReadRequest>) {
                on_read_request(m, replies);
            } else if constexpr (std::is_same_v<T, wire::FoeWriteRequest>) {
                on_write_request(m, replies);
            } else if constexpr (std::is_same_v<T, wire::FoeAck>) {
                on_ack(m, replies);
            } else if constexpr (std::is_same_v<T, wire::FoeData>) {
                on_data(m, replies);
            } else if constexpr (std::is_same_v<T, wire::FoeError>) {
                logger("esc")->debug("FoE: the master gave up '{}': 0x{:04x} {}", file_, m.code, m.text);
                reset();
            } else {
                fail(wire::foe_error::kIllegal, "BUSY is the slave's to send", replies);
            }
        },
        *message);
}

void FoeServer::on_read_request(const wire::FoeReadRequest& request, MailboxReplies& replies) {
    reset();
    if (password_ != 0 && request.password != password_) return fail(wire::foe_error::kNoRights, "wrong password", replies);
    if (files_.find(request.file) == files_.end()) {
        return fail(wire::foe_error::kNotFound, fmt::format("no file '{}'", request.file), replies);
    }
    if (in_packet_ == 0) return fail(wire::foe_error::kProgramError, "SM1 too short for FoE data", replies);
    state_ = State::Reading;
    file_ = request.file;
    send_data(replies);
}

void FoeServer::send_data(MailboxReplies& replies) {
    const auto& file = files_[file_];
    offset_ += in_flight_;
    in_flight_ = std::min(in_packet_, file.size() - std::min(offset_, file.size()));
    ++packet_;
    const auto begin = file.begin() + static_cast<std::ptrdiff_t>(offset_);
    replies.reply(wire::encode_foe(wire::FoeData{packet_, {begin, begin + static_cast<std::ptrdiff_t>(in_flight_)}}));
}

void FoeServer::on_ack(const wire::FoeAck& ack, MailboxReplies& replies) {
    if (state_ != State::Reading) return fail(wire::foe_error::kIllegal, "ACK without a read", replies);
    if (ack.packet != packet_) {
        return fail(wire::foe_error::kPacketNumberWrong, fmt::format("ACK {} for packet {}", ack.packet, packet_),
                    replies);
    }
    if (in_flight_ < in_packet_) {  // the last packet is acknowledged: the file is read
        logger("esc")->debug("FoE: '{}' read ({} bytes)", file_, offset_ + in_flight_);
        reset();
        return;
    }
    send_data(replies);
}

void FoeServer::on_write_request(const wire::FoeWriteRequest& request, MailboxReplies& replies) {
    reset();
    if (password_ != 0 && request.password != password_) return fail(wire::foe_error::kNoRights, "wrong password", replies);
    if (request.file.empty()) return fail(wire::foe_error::kIllegal, "no file name", replies);
    state_ = State::Writing;
    file_ = request.file;
    replies.reply(wire::encode_foe(wire::FoeAck{0}));
}

void FoeServer::on_data(const wire::FoeData& data, MailboxReplies& replies) {
    if (state_ != State::Writing) return fail(wire::foe_error::kIllegal, "DATA without a write", replies);
    if (data.packet != packet_ + 1) {
        return fail(wire::foe_error::kPacketNumberWrong,
                    fmt::format("DATA {} where {} was due", data.packet, packet_ + 1), replies);
    }
    if (busy_packets_ > 0) {
        --busy_packets_;
        const auto done = static_cast<std::uint16_t>(std::min<std::size_t>(data_.size(), 0xFFFF));
        replies.reply(wire::encode_foe(wire::FoeBusy{done, 0, "busy"}));
        return;
    }
    const auto& previous = files_.find(file_);
    const std::size_t replaced = previous == files_.end() ? 0 : previous->second.size();
    if (stored_bytes() - replaced + data_.size() + data.data.size() > room_) {
        return fail(wire::foe_error::kDiskFull, fmt::format("no room for '{}' beyond {} bytes", file_, data_.size()),
                    replies);
    }
    data_.insert(data_.end(), data.data.begin(), data.data.end());
    packet_ = data.packet;
    replies.reply(wire::encode_foe(wire::FoeAck{packet_}));
    if (data.data.size() < out_packet_) {
        logger("esc")->info("FoE: '{}' written ({} bytes)", file_, data_.size());
        files_[file_] = std::move(data_);
        reset();
    }
}

}  // namespace ecpair::sim
