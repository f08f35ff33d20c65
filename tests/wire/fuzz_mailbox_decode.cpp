// Fuzz target: a mailbox message as a slave or master might put it in a
// sync manager: header, CoE header, SDO in both directions, SDO
// Information requests and responses, CoE emergencies, FoE, EoE (header and
// IP parameters) and SoE. Decoded SDO messages must re-encode without
// writing past their own size; decoded SDO Information requests, FoE
// messages and EoE IP parameters must re-encode to what decodes to the same.

#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <vector>

#include <variant>

#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/eoe.hpp"
#include "ecpair/wire/foe.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "ecpair/wire/soe.hpp"

namespace {

void fuzz_foe(ecpair::ConstBytes body) {
    const auto message = ecpair::wire::decode_foe(body);
    if (!message) return;
    const auto again = ecpair::wire::decode_foe(ecpair::wire::encode_foe(*message));
    if (!again || !(*again == *message)) std::abort();
}

void fuzz_eoe(ecpair::ConstBytes body) {
    const auto header = ecpair::wire::EoeHeader::decode(body);
    if (!header) return;
    const auto parameters = ecpair::wire::EoeIpParameters::decode(body.subspan(ecpair::wire::EoeHeader::kSize));
    if (!parameters) return;
    (void)parameters->describe();
    const auto again = ecpair::wire::EoeIpParameters::decode(parameters->encode());
    if (!again || !(*again == *parameters)) std::abort();
}

void fuzz_soe(ecpair::ConstBytes body) {
    const auto header = ecpair::wire::SoeHeader::decode(body);
    if (!header) return;
    std::uint8_t out[ecpair::wire::SoeHeader::kSize];
    header->encode(out);
    if (!std::equal(out, out + sizeof out, body.begin())) std::abort();
    (void)ecpair::wire::idn_text(header->idn_or_fragments);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const ecpair::ConstBytes in(data, size);
    const auto header = ecpair::wire::MailboxHeader::decode(in);
    if (!header) return 0;
    const auto body = in.subspan(ecpair::wire::MailboxHeader::kSize, header->length);
    if (header->type == ecpair::wire::MailboxType::Error) {
        (void)ecpair::wire::MailboxErrorReply::decode(body);
        return 0;
    }
    switch (header->type) {
        case ecpair::wire::MailboxType::FoE: fuzz_foe(body); return 0;
        case ecpair::wire::MailboxType::EoE: fuzz_eoe(body); return 0;
        case ecpair::wire::MailboxType::SoE: fuzz_soe(body); return 0;
        default: break;
    }
    const auto coe = ecpair::wire::CoeHeader::decode(body);
    if (!coe) return 0;
    if (coe->service == ecpair::wire::CoeService::Emergency) {
        (void)ecpair::wire::CoeEmergency::decode(body.subspan(ecpair::wire::CoeHeader::kSize));
        return 0;
    }
    if (coe->service == ecpair::wire::CoeService::SdoInformation) {
        const auto info = body.subspan(ecpair::wire::CoeHeader::kSize);
        const auto request = ecpair::wire::decode_sdo_info_request(info);
        if (const auto* r = std::get_if<ecpair::wire::SdoInfoRequest>(&request)) {
            const auto again = ecpair::wire::decode_sdo_info_request(ecpair::wire::encode_sdo_info_request(*r));
            const auto* same = std::get_if<ecpair::wire::SdoInfoRequest>(&again);
            if (same == nullptr || !(*same == *r)) std::abort();
        }
        if (info.size() >= ecpair::wire::SdoInfoHeader::kSize) {
            const auto service_data = info.subspan(ecpair::wire::SdoInfoHeader::kSize);
            (void)ecpair::wire::OdListResponse::decode(service_data);
            (void)ecpair::wire::ObjectDescription::decode(service_data);
            (void)ecpair::wire::EntryDescription::decode(service_data);
            (void)ecpair::wire::SdoInfoError::decode(service_data);
        }
        return 0;
    }
    for (const bool response : {false, true}) {
        const auto sdo = ecpair::wire::SdoMessage::decode(body.subspan(ecpair::wire::CoeHeader::kSize), response);
        if (!sdo) continue;
        std::vector<std::uint8_t> out(sdo->encoded_size() + 1, 0xA5);
        sdo->encode(ecpair::Bytes(out.data(), sdo->encoded_size()));
        if (out.back() != 0xA5) std::abort();
    }
    return 0;
}
