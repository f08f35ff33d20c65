// The six FoE messages as bytes (see the header): a fixed 6-byte header
// whose UDINT means something else per OpCode, then a name, text or data.

#include "ecpair/wire/foe.hpp"

#include <algorithm>

namespace ecpair::wire {
namespace {

std::string text_of(ConstBytes in) {
    const auto end = std::find(in.begin(), in.end(), std::uint8_t{0});
    return {in.begin(), end};
}

std::vector<std::uint8_t> header(FoeOpcode opcode, std::uint32_t value, std::size_t payload) {
    std::vector<std::uint8_t> out(kFoeHeaderSize + payload, 0);
    out[0] = static_cast<std::uint8_t>(opcode);
    store_le<std::uint32_t>(out, 2, value);
    return out;
}

std::vector<std::uint8_t> with_text(FoeOpcode opcode, std::uint32_t value, std::string_view text) {
    auto out = header(opcode, value, text.size());
    std::copy(text.begin(), text.end(), out.begin() + kFoeHeaderSize);
    return out;
}

}  // namespace

std::vector<std::uint8_t> encode_foe(const FoeMessage& message) {
    return std::visit(
        [](const auto& m) -> std::vector<std::uint8_t> {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, FoeReadRequest>) {
                return with_text(FoeOpcode::Read, m.password, m.file);
            } else if constexpr (std::is_same_v<T, FoeWriteRequest>) {
                return with_text(FoeOpcode::Write, m.password, m.file);
            } else if constexpr (std::is_same_v<T, FoeData>) {
                auto out = header(FoeOpcode::Data, m.packet, m.data.size());
                std::copy(m.data.begin(), m.data.end(), out.begin() + kFoeHeaderSize);
                return out;
            } else if constexpr (std::is_same_v<T, FoeAck>) {
                return header(FoeOpcode::Ack, m.packet, 0);
            } else if constexpr (std::is_same_v<T, FoeError>) {
                return with_text(FoeOpcode::Error, m.code, m.text);
            } else {
                return with_text(FoeOpcode::Busy,
                                 static_cast<std::uint32_t>(m.done) | (static_cast<std::uint32_t>(m.entire) << 16),
                                 m.text);
            }
        },
        message);
}

std::optional<FoeMessage> decode_foe(ConstBytes in) {
    if (in.size() < kFoeHeaderSize) return std::nullopt;
    const std::uint32_t value = load_le<std::uint32_t>(in, 2);
    const ConstBytes rest = in.subspan(kFoeHeaderSize);
    switch (static_cast<FoeOpcode>(in[0])) {
        case FoeOpcode::Read: return FoeMessage{FoeReadRequest{value, text_of(rest)}};
        case FoeOpcode::Write: return FoeMessage{FoeWriteRequest{value, text_of(rest)}};
        case FoeOpcode::Data: return FoeMessage{FoeData{value, {rest.begin(), rest.end()}}};
        case FoeOpcode::Ack: return FoeMessage{FoeAck{value}};
        case FoeOpcode::Error: return FoeMessage{FoeError{value, text_of(rest)}};
        case FoeOpcode::Busy:
            return FoeMessage{FoeBusy{static_cast<std::uint16_t>(value), static_cast<std::uint16_t>(value >> 16),
                                      text_of(rest)}};
    }
    return std::nullopt;
}

std::string_view foe_error_text(std::uint32_t code) {
    switch (code) {
        case foe_error::kNotDefined: return "not defined";
        case foe_error::kNotFound: return "file not found";
        case foe_error::kAccessDenied: return "access denied";
        case foe_error::kDiskFull: return "disk full";
        case foe_error::kIllegal: return "illegal";
        case foe_error::kPacketNumberWrong: return "packet number wrong";
        case foe_error::kAlreadyExists: return "file already exists";
        case foe_error::kNoUser: return "no user";
        case foe_error::kBootstrapOnly: return "bootstrap only";
        case foe_error::kNotBootstrap: return "not in bootstrap";
        case foe_error::kNoRights: return "no rights (wrong password)";
        case foe_error::kProgramError: return "program error";
        default: return "unknown FoE error";
    }
}

}  // namespace ecpair::wire
