// One SDO Information request: the request in one message, then the
// fragments of the answer until the one with no fragments left. Each
// fragment must count down by one; the first fragment may not be preceded
// by a different opcode (other CoE messages are skipped, emergencies are the
// transport's).

#include "ecpair/sequencer/sdo_information_client.hpp"

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sequencer {

struct SdoInformationClient::Query {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::string what;  // "object list (all)", "object 0x1018", "entry 0x1018:01"
    std::chrono::milliseconds timeout;
    std::stop_token stop;

    SdoError error(SdoFailure failure, const std::string& detail) const {
        SdoError e;
        e.failure = failure;
        e.index = index;
        e.subindex = subindex;
        e.message = fmt::format("SDO Information {}: {}", what, detail);
        return e;
    }
};

Expected<std::vector<std::uint16_t>, SdoError> SdoInformationClient::object_list(wire::OdListType list,
                                                                                 std::chrono::milliseconds timeout,
                                                                                 std::stop_token stop) {
    const Query query{0, 0, fmt::format("object list (type {})", static_cast<unsigned>(list)), timeout, stop};
    auto data = transact(query, wire::OdListRequest{list}, wire::SdoInfoOpcode::OdListResponse);
    if (!data) return unexpected(std::move(data).error());
    auto response = wire::OdListResponse::decode(*data);
    if (!response) return unexpected(query.error(SdoFailure::Protocol, "malformed OD list response"));
    if (response->list_type != list) {
        return unexpected(query.error(SdoFailure::Protocol,
                                      fmt::format("the answer lists type {}", static_cast<unsigned>(response->list_type))));
    }
    return std::move(response->indices);
}

Expected<wire::ObjectDescription, SdoError> SdoInformationClient::object_description(std::uint16_t index,
                                                                                     std::chrono::milliseconds timeout,
                                                                                     std::stop_token stop) {
    const Query query{index, 0, fmt::format("object 0x{:04x}", index), timeout, stop};
    auto data = transact(query, wire::ObjectDescriptionRequest{index}, wire::SdoInfoOpcode::ObjectDescriptionResponse);
    if (!data) return unexpected(std::move(data).error());
    auto description = wire::ObjectDescription::decode(*data);
    if (!description) return unexpected(query.error(SdoFailure::Protocol, "malformed object description"));
    if (description->index != index) {
        return unexpected(query.error(SdoFailure::Protocol,
                                      fmt::format("the answer describes object 0x{:04x}", description->index)));
    }
    return std::move(*description);
}

Expected<wire::EntryDescription, SdoError> SdoInformationClient::entry_description(std::uint16_t index,
                                                                                   std::uint8_t subindex,
                                                                                   std::chrono::milliseconds timeout,
                                                                                   std::stop_token stop) {
    const Query query{index, subindex, fmt::format("entry 0x{:04x}:{:02x}", index, subindex), timeout, stop};
    auto data = transact(query, wire::EntryDescriptionRequest{index, subindex, 0},
                         wire::SdoInfoOpcode::EntryDescriptionResponse);
    if (!data) return unexpected(std::move(data).error());
    auto description = wire::EntryDescription::decode(*data);
    if (!description) return unexpected(query.error(SdoFailure::Protocol, "malformed entry description"));
    if (description->index != index || description->subindex != subindex) {
        return unexpected(query.error(SdoFailure::Protocol,
                                      fmt::format("the answer describes entry 0x{:04x}:{:02x}", description->index,
                                                  description->subindex)));
    }
    return std::move(*description);
}

Expected<std::vector<std::uint8_t>, SdoError> SdoInformationClient::transact(const Query& query,
                                                                              const wire::SdoInfoRequest& request,
                                                                              wire::SdoInfoOpcode answer) {
    const auto from_mailbox = [&query](const MailboxError& e) {
        return sdo_error_from(e, query.index, query.subindex, "SDO Information " + query.what);
    };
    const auto service_data = wire::encode_sdo_info_request(request);
    std::vector<std::uint8_t> message(wire::CoeHeader::kSize + service_data.size());
    wire::CoeHeader{0, wire::CoeService::SdoInformation}.encode(message);
    std::copy(service_data.begin(), service_data.end(), message.begin() + wire::CoeHeader::kSize);

    // Every fragment has its own time: a long list is many messages.
    auto deadline = clock_.now() + query.timeout;
    if (auto sent = transport_.send_message(wire::MailboxType::CoE, message, deadline, query.stop); !sent) {
        return unexpected(from_mailbox(sent.error()));
    }
    std::vector<std::uint8_t> joined;
    std::optional<std::uint16_t> fragments_left;
    for (;;) {
        auto body = transport_.receive_message(wire::MailboxType::CoE, deadline, query.stop);
        if (!body) return unexpected(from_mailbox(body.error()));
        const auto coe = wire::CoeHeader::decode(*body);
        if (!coe) return unexpected(query.error(SdoFailure::Protocol, "CoE header missing in the reply"));
        if (coe->service != wire::CoeService::SdoInformation) {
            logger("sequencer")->debug("station {}: skipped a CoE message of service {} during SDO Information {}",
                                       transport_.channel().station, static_cast<unsigned>(coe->service), query.what);
            continue;
        }
        const auto info = ConstBytes(*body).subspan(wire::CoeHeader::kSize);
        const auto header = wire::SdoInfoHeader::decode(info);
        if (!header) return unexpected(query.error(SdoFailure::Protocol, "SDO Information header missing"));
        const auto data = info.subspan(wire::SdoInfoHeader::kSize);
        if (header->opcode == wire::SdoInfoOpcode::Error) {
            const auto error = wire::SdoInfoError::decode(data);
            const std::uint32_t code = error ? error->abort_code : 0;
            auto e = query.error(SdoFailure::Abort, fmt::format("aborted: 0x{:08x} {}", code, wire::sdo_abort_text(code)));
            e.abort_code = code;
            return unexpected(std::move(e));
        }
        if (header->opcode != answer) {
            return unexpected(query.error(SdoFailure::Protocol,
                                          fmt::format("opcode {} instead of {}", static_cast<unsigned>(header->opcode),
                                                      static_cast<unsigned>(answer))));
        }
        if (fragments_left && header->fragments_left + 1 != *fragments_left) {
            return unexpected(query.error(SdoFailure::Protocol,
                                          fmt::format("fragment with {} left after one with {} left",
                                                      header->fragments_left, *fragments_left)));
        }
        joined.insert(joined.end(), data.begin(), data.end());
        if (!header->incomplete) return joined;
        if (header->fragments_left == 0) {
            return unexpected(query.error(SdoFailure::Protocol, "incomplete fragment with no fragments left"));
        }
        fragments_left = header->fragments_left;
        deadline = clock_.now() + query.timeout;
    }
}

}  // namespace ecpair::sequencer
