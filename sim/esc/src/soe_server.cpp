// IDN reads and writes of the emulated drive (see the header).

#include "ecpair/sim/soe_server.hpp"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"

namespace ecpair::sim {
namespace {

constexpr std::uint16_t kNoIdn = 0x1001;
constexpr std::uint16_t kNameReadOnly = 0x2004;
constexpr std::uint16_t kAttributeReadOnly = 0x3004;
constexpr std::uint16_t kNoUnit = 0x4001;
constexpr std::uint16_t kNoMinimum = 0x5001;
constexpr std::uint16_t kNoMaximum = 0x6001;
constexpr std::uint16_t kNoDefault = 0x8001;
constexpr std::uint16_t kInvalidDrive = 0x800A;
constexpr std::uint16_t kNoElement = 0x800C;

constexpr std::uint16_t kDiagnostic = 11;
constexpr std::uint16_t kTelegramType = 15;
constexpr std::uint16_t kIdnList = 17;

std::vector<std::uint8_t> le16(std::uint16_t v) {
    return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)};
}

// A Sercos list or string: actual length, maximum length (bytes), then the data.
std::vector<std::uint8_t> sercos_list(const std::vector<std::uint8_t>& data) {
    auto out = le16(static_cast<std::uint16_t>(data.size()));
    const auto max = le16(static_cast<std::uint16_t>(data.size()));
    out.insert(out.end(), max.begin(), max.end());
    out.insert(out.end(), data.begin(), data.end());
    return out;
}

std::vector<std::uint8_t> body_of(const wire::SoeHeader& header, ConstBytes data) {
    std::vector<std::uint8_t> body(wire::SoeHeader::kSize + data.size());
    header.encode(body);
    std::copy(data.begin(), data.end(), body.begin() + wire::SoeHeader::kSize);
    return body;
}

}  // namespace

SoeServer::SoeServer(const std::vector<eni::SoeInitCmd>& init_cmds) {
    std::set<std::uint8_t> drives{0};
    for (const auto& cmd : init_cmds) drives.insert(cmd.drive_no);
    for (const auto drive : drives) {
        idns_[{drive, kDiagnostic}] = Idn{"Class 1 diagnostic", 0x00050000, le16(0)};
        idns_[{drive, kTelegramType}] = Idn{"Telegram type parameter", 0x00050000, le16(7)};
    }
    for (const auto& cmd : init_cmds) {
        auto& idn = idns_[{cmd.drive_no, cmd.idn}];
        if (idn.name.empty()) idn.name = fmt::format("{} (from the ENI)", wire::idn_text(cmd.idn));
        if (idn.value.size() != cmd.data.size()) idn.value.assign(cmd.data.size(), 0);
    }
    for (const auto drive : drives) {
        std::vector<std::uint8_t> list;
        for (const auto& [key, idn] : idns_) {
            if (key.first != drive) continue;
            const auto number = le16(key.second);
            list.insert(list.end(), number.begin(), number.end());
        }
        const auto number = le16(kIdnList);
        list.insert(list.end(), number.begin(), number.end());
        idns_[{drive, kIdnList}] = Idn{"IDN-list of all operation data", 0x00050000, sercos_list(list)};
    }
}

const SoeServer::Idn* SoeServer::idn(std::uint8_t drive, std::uint16_t number) const {
    const auto found = idns_.find({drive, number});
    return found == idns_.end() ? nullptr : &found->second;
}

void SoeServer::reset() {
    fragments_.clear();
    written_.clear();
}

void SoeServer::fail(wire::SoeOpcode answer, const wire::SoeHeader& request, std::uint16_t code,
                     MailboxReplies& replies) {
    logger("esc")->debug("SoE: {} of drive {}: error 0x{:04x} ({})", wire::idn_text(request.idn_or_fragments),
                         request.drive, code, wire::soe_error_text(code));
    written_.clear();
    wire::SoeHeader header = request;
    header.opcode = answer;
    header.error = true;
    header.incomplete = false;
    replies.reply(body_of(header, le16(code)));
}

void SoeServer::on_request(ConstBytes body, MailboxReplies& replies) {
    const auto header = wire::SoeHeader::decode(body);
    if (!header) return replies.error(0x0006);  // too short for the SoE header
    switch (header->opcode) {
        case wire::SoeOpcode::ReadRequest: return read(*header, replies);
        case wire::SoeOpcode::WriteRequest: return write(*header, body.subspan(wire::SoeHeader::kSize), replies);
        default:
            logger("esc")->debug("SoE: opcode {} from the master dropped", static_cast<unsigned>(header->opcode));
            return;
    }
}

void SoeServer::read(const wire::SoeHeader& request, MailboxReplies& replies) {
    const auto answer = wire::SoeOpcode::ReadResponse;
    const auto found = idns_.find({request.drive, request.idn_or_fragments});
    if (found == idns_.end()) {
        const bool drive_known = std::any_of(idns_.begin(), idns_.end(),
                                             [&](const auto& entry) { return entry.first.first == request.drive; });
        return fail(answer, request, drive_known ? kNoIdn : kInvalidDrive, replies);
    }
    const Idn& idn = found->second;
    std::vector<std::uint8_t> data;
    if ((request.elements & wire::soe_elements::kValue) != 0) {
        data = idn.value;
    } else if ((request.elements & wire::soe_elements::kName) != 0) {
        data = sercos_list({idn.name.begin(), idn.name.end()});
    } else if ((request.elements & wire::soe_elements::kAttribute) != 0) {
        data = {static_cast<std::uint8_t>(idn.attribute), static_cast<std::uint8_t>(idn.attribute >> 8),
                static_cast<std::uint8_t>(idn.attribute >> 16), static_cast<std::uint8_t>(idn.attribute >> 24)};
    } else if ((request.elements & wire::soe_elements::kDataState) != 0) {
        data = le16(0);
    } else if ((request.elements & wire::soe_elements::kUnit) != 0) {
        return fail(answer, request, kNoUnit, replies);
    } else if ((request.elements & wire::soe_elements::kMinimum) != 0) {
        return fail(answer, request, kNoMinimum, replies);
    } else if ((request.elements & wire::soe_elements::kMaximum) != 0) {
        return fail(answer, request, kNoMaximum, replies);
    } else if ((request.elements & wire::soe_elements::kDefault) != 0) {
        return fail(answer, request, kNoDefault, replies);
    } else {
        return fail(answer, request, kNoElement, replies);
    }
    // Fragments as long as SM1 allows; every one but the last counts the ones after it.
    const std::size_t capacity = replies.capacity() > wire::SoeHeader::kSize ? replies.capacity() - wire::SoeHeader::kSize : 0;
    if (capacity == 0) return;
    const std::size_t count = data.empty() ? 1 : (data.size() + capacity - 1) / capacity;
    fragments_.clear();
    for (std::size_t i = 0; i < count; ++i) {
        wire::SoeHeader header = request;
        header.opcode = answer;
        header.incomplete = i + 1 < count;
        header.idn_or_fragments = header.incomplete ? static_cast<std::uint16_t>(count - 1 - i) : request.idn_or_fragments;
        const std::size_t offset = i * capacity;
        fragments_.push_back(body_of(header, ConstBytes(data).subspan(offset, std::min(capacity, data.size() - offset))));
    }
    on_reply_read(replies);
}

void SoeServer::on_reply_read(MailboxReplies& replies) {
    if (fragments_.empty()) return;
    replies.reply(fragments_.front());
    fragments_.pop_front();
}

void SoeServer::write(const wire::SoeHeader& request, ConstBytes data, MailboxReplies& replies) {
    const auto answer = wire::SoeOpcode::WriteResponse;
    written_.insert(written_.end(), data.begin(), data.end());
    if (request.incomplete) return;  // more fragments follow; the last one is answered
    std::vector<std::uint8_t> value;
    value.swap(written_);
    if ((request.elements & wire::soe_elements::kValue) == 0) {
        if ((request.elements & wire::soe_elements::kName) != 0) return fail(answer, request, kNameReadOnly, replies);
        if ((request.elements & wire::soe_elements::kAttribute) != 0) {
            return fail(answer, request, kAttributeReadOnly, replies);
        }
        return fail(answer, request, kNoElement, replies);
    }
    const auto found = idns_.find({request.drive, request.idn_or_fragments});
    if (found == idns_.end()) {
        const bool drive_known = std::any_of(idns_.begin(), idns_.end(),
                                             [&](const auto& entry) { return entry.first.first == request.drive; });
        return fail(answer, request, drive_known ? kNoIdn : kInvalidDrive, replies);
    }
    found->second.value = std::move(value);
    logger("esc")->debug("SoE: drive {} {} = {} byte(s)", request.drive, wire::idn_text(request.idn_or_fragments),
                        found->second.value.size());
    wire::SoeHeader header = request;
    header.opcode = answer;
    replies.reply(body_of(header, {}));
}

}  // namespace ecpair::sim
