// Little-endian codecs of the SDO Information messages (see the header).
// Names are the rest of a message: no terminator on the wire; a decoder
// stops at the end of the data (or at a NUL some slaves append).

#include "ecpair/wire/sdo_information.hpp"

#include <algorithm>

namespace ecpair::wire {
namespace {

constexpr std::uint8_t kIncomplete = 0x80;
constexpr std::uint8_t kOpcodeMask = 0x7F;
constexpr std::size_t kObjectDescriptionFixed = 6;
constexpr std::size_t kEntryDescriptionFixed = 10;

void put16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    put16(out, static_cast<std::uint16_t>(v));
    put16(out, static_cast<std::uint16_t>(v >> 16));
}

std::string name_of(ConstBytes in) {
    const auto end = std::find(in.begin(), in.end(), std::uint8_t{0});
    return {in.begin(), end};
}

}  // namespace

void SdoInfoHeader::encode(Bytes out) const {
    out[0] = static_cast<std::uint8_t>((static_cast<std::uint8_t>(opcode) & kOpcodeMask) | (incomplete ? kIncomplete : 0));
    out[1] = 0;
    store_le<std::uint16_t>(out, 2, fragments_left);
}

std::optional<SdoInfoHeader> SdoInfoHeader::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    return SdoInfoHeader{static_cast<SdoInfoOpcode>(in[0] & kOpcodeMask), (in[0] & kIncomplete) != 0,
                         load_le<std::uint16_t>(in, 2)};
}

std::variant<SdoInfoRequest, SdoInfoDecodeError> decode_sdo_info_request(ConstBytes in) {
    const auto header = SdoInfoHeader::decode(in);
    if (!header) return SdoInfoDecodeError{0, "shorter than the 4-byte SDO Information header"};
    if (header->incomplete || header->fragments_left != 0) {
        return SdoInfoDecodeError{0, "a fragmented request (no request is longer than one mailbox)"};
    }
    const ConstBytes data = in.subspan(SdoInfoHeader::kSize);
    const auto need = [&](std::size_t bytes, const char* what) -> std::optional<SdoInfoDecodeError> {
        if (data.size() >= bytes) return std::nullopt;
        return SdoInfoDecodeError{SdoInfoHeader::kSize + data.size(), what};
    };
    switch (header->opcode) {
        case SdoInfoOpcode::OdListRequest:
            if (auto e = need(2, "Get OD List request without its list type")) return *e;
            return SdoInfoRequest{OdListRequest{static_cast<OdListType>(load_le<std::uint16_t>(data, 0))}};
        case SdoInfoOpcode::ObjectDescriptionRequest:
            if (auto e = need(2, "Get Object Description request without its index")) return *e;
            return SdoInfoRequest{ObjectDescriptionRequest{load_le<std::uint16_t>(data, 0)}};
        case SdoInfoOpcode::EntryDescriptionRequest:
            if (auto e = need(4, "Get Entry Description request shorter than index, subindex and value info")) return *e;
            return SdoInfoRequest{EntryDescriptionRequest{load_le<std::uint16_t>(data, 0), data[2], data[3]}};
        case SdoInfoOpcode::Error:
            if (auto e = need(4, "SDO Info Error request without its abort code")) return *e;
            return SdoInfoRequest{SdoInfoErrorRequest{load_le<std::uint32_t>(data, 0)}};
        case SdoInfoOpcode::OdListResponse:
        case SdoInfoOpcode::ObjectDescriptionResponse:
        case SdoInfoOpcode::EntryDescriptionResponse: break;
    }
    return SdoInfoDecodeError{0, "opcode " + std::to_string(static_cast<unsigned>(header->opcode)) + " is not a request"};
}

std::vector<std::uint8_t> encode_sdo_info_request(const SdoInfoRequest& request) {
    std::vector<std::uint8_t> out(SdoInfoHeader::kSize);
    SdoInfoOpcode opcode = SdoInfoOpcode::OdListRequest;
    if (const auto* list = std::get_if<OdListRequest>(&request)) {
        put16(out, static_cast<std::uint16_t>(list->list_type));
    } else if (const auto* object = std::get_if<ObjectDescriptionRequest>(&request)) {
        opcode = SdoInfoOpcode::ObjectDescriptionRequest;
        put16(out, object->index);
    } else if (const auto* entry = std::get_if<EntryDescriptionRequest>(&request)) {
        opcode = SdoInfoOpcode::EntryDescriptionRequest;
        put16(out, entry->index);
        out.push_back(entry->subindex);
        out.push_back(entry->value_info);
    } else {
        opcode = SdoInfoOpcode::Error;
        put32(out, std::get<SdoInfoErrorRequest>(request).abort_code);
    }
    SdoInfoHeader{opcode, false, 0}.encode(out);
    return out;
}

std::vector<std::uint8_t> OdListResponse::encode() const {
    std::vector<std::uint8_t> out;
    out.reserve(2 + 2 * indices.size());
    put16(out, static_cast<std::uint16_t>(list_type));
    for (const auto index : indices) put16(out, index);
    return out;
}

std::optional<OdListResponse> OdListResponse::decode(ConstBytes in) {
    if (in.size() < 2 || in.size() % 2 != 0) return std::nullopt;
    OdListResponse r;
    r.list_type = static_cast<OdListType>(load_le<std::uint16_t>(in, 0));
    for (std::size_t at = 2; at < in.size(); at += 2) r.indices.push_back(load_le<std::uint16_t>(in, at));
    return r;
}

std::vector<std::uint8_t> ObjectDescription::encode() const {
    std::vector<std::uint8_t> out;
    put16(out, index);
    put16(out, data_type);
    out.push_back(max_subindex);
    out.push_back(object_code);
    out.insert(out.end(), name.begin(), name.end());
    return out;
}

std::optional<ObjectDescription> ObjectDescription::decode(ConstBytes in) {
    if (in.size() < kObjectDescriptionFixed) return std::nullopt;
    return ObjectDescription{load_le<std::uint16_t>(in, 0), load_le<std::uint16_t>(in, 2), in[4], in[5],
                             name_of(in.subspan(kObjectDescriptionFixed))};
}

std::vector<std::uint8_t> EntryDescription::encode() const {
    std::vector<std::uint8_t> out;
    put16(out, index);
    out.push_back(subindex);
    out.push_back(0);  // value info: no unit, default, minimum or maximum follow
    put16(out, data_type);
    put16(out, bit_length);
    put16(out, object_access);
    out.insert(out.end(), name.begin(), name.end());
    return out;
}

std::optional<EntryDescription> EntryDescription::decode(ConstBytes in) {
    if (in.size() < kEntryDescriptionFixed) return std::nullopt;
    EntryDescription e{load_le<std::uint16_t>(in, 0), in[2], in[3], load_le<std::uint16_t>(in, 4),
                       load_le<std::uint16_t>(in, 6), load_le<std::uint16_t>(in, 8), {}};
    // Unit (UDINT) and default/minimum/maximum (as long as the entry) may sit between the fixed part and the name.
    std::size_t at = kEntryDescriptionFixed;
    const std::size_t value_bytes = (e.bit_length + 7u) / 8u;
    if ((e.value_info & 0x08) != 0) at += 4;
    for (const std::uint8_t bit : {std::uint8_t{0x10}, std::uint8_t{0x20}, std::uint8_t{0x40}}) {
        if ((e.value_info & bit) != 0) at += value_bytes;
    }
    if (at > in.size()) return std::nullopt;
    e.name = name_of(in.subspan(at));
    return e;
}

std::vector<std::uint8_t> SdoInfoError::encode() const {
    std::vector<std::uint8_t> out;
    put32(out, abort_code);
    return out;
}

std::optional<SdoInfoError> SdoInfoError::decode(ConstBytes in) {
    if (in.size() < 4) return std::nullopt;
    return SdoInfoError{load_le<std::uint32_t>(in, 0)};
}

}  // namespace ecpair::wire
