// Serves one SDO request at a time. Initiate requests address an object;
// segments continue the transfer of the last initiate. A new initiate while
// a segmented transfer is open abandons it, as a master that gave up on a
// transfer starts the next one without an abort.
//
// Sizes: an initiate reply is 8 bytes plus, for a normal upload, the data;
// a segment reply is 1 byte plus up to reply_capacity - 1 bytes of data
// (at least 7 on the wire: shorter segments are padded and say so).

#include "sdo_server.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"

namespace ecpair::sim {
namespace {

namespace sdo_abort = wire::sdo_abort;

constexpr std::size_t kExpeditedMax = 4;

}  // namespace

std::string_view to_string(SdoTransferState state) {
    switch (state) {
        case SdoTransferState::Idle: return "idle";
        case SdoTransferState::SegmentedDownload: return "segmented download";
        case SdoTransferState::SegmentedUpload: return "segmented upload";
    }
    return "?";
}

SdoServer::SdoServer(ObjectDictionary& dictionary, CoeSlaveContext& slave, std::size_t reply_capacity)
    : dictionary_(dictionary), slave_(slave), reply_capacity_(std::max(reply_capacity, wire::SdoMessage::kHeaderSize)) {}

std::optional<wire::SdoMessage> SdoServer::handle(const wire::SdoMessage& request) {
    switch (request.command) {
        case wire::SdoCommand::Download:
        case wire::SdoCommand::Upload:
            if (state_ != SdoTransferState::Idle) enter(SdoTransferState::Idle, "abandoned for a new request");
            address_ = SdoAddress{request.index, request.subindex, request.complete_access};
            return request.command == wire::SdoCommand::Download ? initiate_download(request) : initiate_upload(request);
        case wire::SdoCommand::DownloadSegment: return download_segment(request);
        case wire::SdoCommand::UploadSegment: return upload_segment(request);
        case wire::SdoCommand::Abort:
            if (state_ != SdoTransferState::Idle) {
                enter(SdoTransferState::Idle, fmt::format("the master aborted with {:#010x} ({})", request.complete_size,
                                                       wire::sdo_abort_text(request.complete_size)));
            }
            return std::nullopt;
    }
    return abort(sdo_abort::kUnknownCommand);
}

void SdoServer::reset() {
    if (state_ != SdoTransferState::Idle) enter(SdoTransferState::Idle, "the mailbox stopped");
}

void SdoServer::enter(SdoTransferState next, std::string_view why) {
    logger("esc")->debug("station {:#06x}: SDO {:#06x}:{:02x} {} -> {}: {}", slave_.station_address(), address_.index,
                         address_.subindex,
                         to_string(state_), to_string(next), why);
    state_ = next;
    if (next == SdoTransferState::Idle) data_.clear();
}

wire::SdoMessage SdoServer::initiate_download(const wire::SdoMessage& request) {
    if (request.expedited || request.data.size() >= request.complete_size) {
        if (auto stored = store(request.data); !stored) return abort(stored.error());
        return response(wire::SdoCommand::Download);
    }
    // The rest follows in segments: refuse now what the whole could not be.
    if (auto acceptable = dictionary_.check_download(address_, request.complete_size, slave_.al_state()); !acceptable) {
        return abort(acceptable.error());
    }
    data_ = request.data;
    announced_size_ = request.complete_size;
    toggle_ = false;
    enter(SdoTransferState::SegmentedDownload, fmt::format("{} of {} bytes", data_.size(), announced_size_));
    return response(wire::SdoCommand::Download);
}

wire::SdoMessage SdoServer::download_segment(const wire::SdoMessage& request) {
    if (state_ != SdoTransferState::SegmentedDownload) {
        address_ = SdoAddress{};
        return abort(sdo_abort::kUnknownCommand);
    }
    if (request.toggle != toggle_) return abort(sdo_abort::kToggleBit);
    if (data_.size() + request.data.size() > announced_size_) return abort(sdo_abort::kLengthMismatch);
    data_.insert(data_.end(), request.data.begin(), request.data.end());
    toggle_ = !toggle_;
    if (request.last_segment) {
        if (data_.size() != announced_size_) return abort(sdo_abort::kLengthMismatch);
        const std::vector<std::uint8_t> received = std::move(data_);
        enter(SdoTransferState::Idle, "last segment received");
        if (auto stored = store(received); !stored) return abort(stored.error());
    }
    wire::SdoMessage reply = response(wire::SdoCommand::DownloadSegment);
    reply.toggle = request.toggle;
    return reply;
}

wire::SdoMessage SdoServer::initiate_upload(const wire::SdoMessage& request) {
    auto value = dictionary_.upload(address_);
    if (!value) return abort(value.error());
    wire::SdoMessage reply = response(wire::SdoCommand::Upload);
    reply.complete_access = request.complete_access;
    const std::size_t size = value->size();
    if (size >= 1 && size <= kExpeditedMax) {
        reply.expedited = true;
        reply.size_indicated = true;
        reply.data = std::move(*value);
        return reply;
    }
    reply.size_indicated = true;
    reply.complete_size = static_cast<std::uint32_t>(size);
    const std::size_t room = reply_capacity_ - wire::SdoMessage::kHeaderSize;
    if (size <= room) {
        reply.data = std::move(*value);
        return reply;
    }
    reply.data.assign(value->begin(), value->begin() + static_cast<std::ptrdiff_t>(room));
    data_ = std::move(*value);
    uploaded_ = room;
    toggle_ = false;
    enter(SdoTransferState::SegmentedUpload, fmt::format("{} of {} bytes", uploaded_, data_.size()));
    return reply;
}

wire::SdoMessage SdoServer::upload_segment(const wire::SdoMessage& request) {
    if (state_ != SdoTransferState::SegmentedUpload) {
        address_ = SdoAddress{};
        return abort(sdo_abort::kUnknownCommand);
    }
    if (request.toggle != toggle_) return abort(sdo_abort::kToggleBit);
    const std::size_t length =
        std::min(data_.size() - uploaded_, reply_capacity_ - wire::SdoMessage::kSegmentHeader);
    wire::SdoMessage reply = response(wire::SdoCommand::UploadSegment);
    reply.toggle = request.toggle;
    reply.data.assign(data_.begin() + static_cast<std::ptrdiff_t>(uploaded_),
                      data_.begin() + static_cast<std::ptrdiff_t>(uploaded_ + length));
    uploaded_ += length;
    toggle_ = !toggle_;
    reply.last_segment = uploaded_ == data_.size();
    if (reply.last_segment) enter(SdoTransferState::Idle, "last segment sent");
    return reply;
}

Expected<void, SdoAbortCode> SdoServer::store(ConstBytes data) {
    auto stored = dictionary_.download(address_, data, slave_.al_state());
    if (!stored) return stored;
    logger("esc")->debug("station {:#06x}: SDO download {:#06x}:{:02x}{}, {} bytes", slave_.station_address(),
                         address_.index, address_.subindex, address_.complete_access ? " (complete access)" : "",
                         data.size());
    if (ObjectDictionary::is_pdo_configuration(address_.index)) {
        for (const std::uint8_t sm : dictionary_.assigned_sync_managers()) {
            slave_.process_data_size_changed(sm, dictionary_.process_data_bytes(sm));
        }
    }
    return {};
}

wire::SdoMessage SdoServer::abort(SdoAbortCode code) {
    logger("esc")->debug("station {:#06x}: SDO {:#06x}:{:02x} aborted: {:#010x} {}", slave_.station_address(),
                         address_.index, address_.subindex, code, wire::sdo_abort_text(code));
    if (state_ != SdoTransferState::Idle) enter(SdoTransferState::Idle, fmt::format("aborted with {:#010x}", code));
    return wire::SdoMessage::abort(address_.index, address_.subindex, code);
}

wire::SdoMessage SdoServer::response(wire::SdoCommand command) const {
    wire::SdoMessage reply;
    reply.command = command;
    reply.is_response = true;
    reply.index = address_.index;
    reply.subindex = address_.subindex;
    reply.complete_access = address_.complete_access;
    return reply;
}

}  // namespace ecpair::sim
