// The fake mailbox slave (see the header). Complete access is served on
// subindex 0 as the whole object: SI0 as two bytes followed by the entries,
// the way the ENI writes it.

#include "fake_mailbox_slave.hpp"

#include <algorithm>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::test {
namespace {

constexpr std::uint16_t kSm1Status = 0x080D;
constexpr std::size_t kOverhead = wire::MailboxHeader::kSize + wire::CoeHeader::kSize;

}  // namespace

Expected<bus::DatagramReply, bus::BusError> FakeMailboxSlave::exchange(const bus::DatagramRequest& request) {
    const auto adp = static_cast<std::uint16_t>(request.address & 0xFFFF);
    const auto ado = static_cast<std::uint16_t>(request.address >> 16);
    bus::DatagramReply reply{request.data, 0};
    if (adp != kStation) return reply;
    const auto ch = channel();
    if (request.command == wire::Command::Fpwr && ado == ch.send.start && request.data.size() == ch.send.length) {
        if (sm0_busy_writes > 0) {
            --sm0_busy_writes;
            ++sm0_writes_refused;
            return reply;
        }
        reply.wkc = 1;
        on_request(request.data);
    } else if (request.command == wire::Command::Fprd && ado == kSm1Status && request.data.size() == 1) {
        reply.data[0] = sm1_.empty() ? 0x00 : 0x08;
        reply.wkc = 1;
    } else if (request.command == wire::Command::Fprd && ado == ch.recv.start && request.data.size() == ch.recv.length) {
        if (!sm1_.empty()) {
            std::fill(reply.data.begin(), reply.data.end(), std::uint8_t{0});
            std::copy(sm1_.front().begin(), sm1_.front().end(), reply.data.begin());
            sm1_.pop_front();
            reply.wkc = 1;
        }
    }
    return reply;
}

void FakeMailboxSlave::post(std::vector<std::uint8_t> message) { sm1_.push_back(std::move(message)); }

void FakeMailboxSlave::on_request(const std::vector<std::uint8_t>& buffer) {
    const auto header = wire::MailboxHeader::decode(buffer);
    if (!header) return;
    counters.push_back(header->counter);
    const auto body = ConstBytes(buffer).subspan(wire::MailboxHeader::kSize, header->length);
    auto sdo = wire::SdoMessage::decode(body.subspan(wire::CoeHeader::kSize), false);
    if (!sdo) return;
    requests.push_back(*sdo);
    if (!answer) return;
    if (mailbox_error) {
        std::vector<std::uint8_t> message(wire::MailboxHeader::kSize + wire::MailboxErrorReply::kSize, 0);
        wire::MailboxHeader h;
        h.length = wire::MailboxErrorReply::kSize;
        h.address = kStation;
        h.type = wire::MailboxType::Error;
        h.encode(message);
        wire::MailboxErrorReply{*mailbox_error}.encode(Bytes(message).subspan(wire::MailboxHeader::kSize));
        mailbox_error.reset();
        post(std::move(message));
        return;
    }
    if (emergency_first) {
        emergency_first = false;
        std::vector<std::uint8_t> message(kOverhead + 8, 0);
        wire::MailboxHeader h;
        h.length = wire::CoeHeader::kSize + 8;
        h.address = kStation;
        h.type = wire::MailboxType::CoE;
        h.encode(message);
        wire::CoeHeader{0, wire::CoeService::Emergency}.encode(Bytes(message).subspan(wire::MailboxHeader::kSize));
        message[kOverhead] = 0x10;  // error code 0x8110 (CAN overrun)
        message[kOverhead + 1] = 0x81;
        post(std::move(message));
    }
    serve(*sdo);
}

void FakeMailboxSlave::serve(const wire::SdoMessage& request) {
    using wire::SdoCommand;
    wire::SdoMessage response;
    response.is_response = true;
    response.index = request.index;
    response.subindex = request.subindex;
    const auto key = std::make_pair(request.index, request.subindex);
    const std::size_t first_capacity = kMailboxLength - kOverhead - wire::SdoMessage::kHeaderSize;
    const std::size_t segment_capacity = kMailboxLength - kOverhead - wire::SdoMessage::kSegmentHeader;

    switch (request.command) {
        case SdoCommand::Download: {
            if (!objects.count(key)) return respond(wire::SdoMessage::abort(request.index, request.subindex,
                                                                             wire::sdo_abort::kObjectDoesNotExist));
            response.command = SdoCommand::Download;
            if (request.expedited || request.data.size() == request.complete_size) {
                objects[key] = request.data;
            } else {
                download_target_ = key;
                download_data_ = request.data;
                toggle_ = false;
            }
            return respond(response);
        }
        case SdoCommand::DownloadSegment: {
            if (!download_target_ || request.toggle != toggle_) {
                return respond(wire::SdoMessage::abort(0, 0, wire::sdo_abort::kToggleBit));
            }
            download_data_.insert(download_data_.end(), request.data.begin(), request.data.end());
            response.command = SdoCommand::DownloadSegment;
            response.toggle = toggle_;
            toggle_ = !toggle_;
            if (request.last_segment) {
                objects[*download_target_] = download_data_;
                download_target_.reset();
            }
            return respond(response);
        }
        case SdoCommand::Upload: {
            const auto found = objects.find(key);
            if (found == objects.end()) return respond(wire::SdoMessage::abort(request.index, request.subindex,
                                                                                wire::sdo_abort::kObjectDoesNotExist));
            const auto& value = found->second;
            response.command = SdoCommand::Upload;
            if (value.size() <= 4 && !request.complete_access) {
                response.expedited = true;
                response.size_indicated = true;
                response.data = value;
                return respond(response);
            }
            response.complete_size = static_cast<std::uint32_t>(value.size());
            const std::size_t first = std::min(value.size(), first_capacity);
            response.data.assign(value.begin(), value.begin() + static_cast<std::ptrdiff_t>(first));
            upload_rest_.assign(value.begin() + static_cast<std::ptrdiff_t>(first), value.end());
            toggle_ = false;
            return respond(response);
        }
        case SdoCommand::UploadSegment: {
            if (request.toggle != toggle_) return respond(wire::SdoMessage::abort(0, 0, wire::sdo_abort::kToggleBit));
            const std::size_t n = std::min(upload_rest_.size(), segment_capacity);
            response.command = SdoCommand::UploadSegment;
            response.toggle = toggle_;
            response.data.assign(upload_rest_.begin(), upload_rest_.begin() + static_cast<std::ptrdiff_t>(n));
            upload_rest_.erase(upload_rest_.begin(), upload_rest_.begin() + static_cast<std::ptrdiff_t>(n));
            response.last_segment = upload_rest_.empty();
            toggle_ = !toggle_;
            return respond(response);
        }
        case SdoCommand::Abort: return;
    }
}

void FakeMailboxSlave::respond(const wire::SdoMessage& response) {
    auto sdo = response;
    sdo.is_response = true;
    std::vector<std::uint8_t> message(kOverhead + sdo.encoded_size(), 0);
    wire::MailboxHeader h;
    h.length = static_cast<std::uint16_t>(wire::CoeHeader::kSize + sdo.encoded_size());
    h.address = kStation;
    h.type = wire::MailboxType::CoE;
    h.encode(message);
    wire::CoeHeader{0, wire::CoeService::SdoResponse}.encode(Bytes(message).subspan(wire::MailboxHeader::kSize));
    sdo.encode(Bytes(message).subspan(kOverhead));
    post(std::move(message));
}

}  // namespace ecpair::test
