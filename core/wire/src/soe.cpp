// The SoE header as bytes and the texts of IDNs and error codes (see the header).

#include "ecpair/wire/soe.hpp"

#include <fmt/format.h>

namespace ecpair::wire {

void SoeHeader::encode(Bytes out) const {
    out[0] = static_cast<std::uint8_t>((static_cast<std::uint8_t>(opcode) & 0x07) | (incomplete ? 0x08 : 0) |
                                       (error ? 0x10 : 0) | ((drive & 0x07) << 5));
    out[1] = elements;
    store_le<std::uint16_t>(out, 2, idn_or_fragments);
}

std::optional<SoeHeader> SoeHeader::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    SoeHeader h;
    h.opcode = static_cast<SoeOpcode>(in[0] & 0x07);
    h.incomplete = (in[0] & 0x08) != 0;
    h.error = (in[0] & 0x10) != 0;
    h.drive = static_cast<std::uint8_t>(in[0] >> 5);
    h.elements = in[1];
    h.idn_or_fragments = load_le<std::uint16_t>(in, 2);
    return h;
}

std::string idn_text(std::uint16_t idn) {
    return fmt::format("{}-{}-{:04}", (idn & 0x8000) != 0 ? 'P' : 'S', (idn >> 12) & 0x07, idn & 0x0FFF);
}

std::string_view soe_error_text(std::uint16_t code) {
    switch (code) {
        case 0x0000: return "no error";
        case 0x1001: return "IDN not in the drive";
        case 0x1009: return "invalid access to element 1";
        case 0x2001: return "no name";
        case 0x2002: return "name transmission too short";
        case 0x2003: return "name transmission too long";
        case 0x2004: return "name cannot be changed (read only)";
        case 0x2005: return "name is write-protected at this time";
        case 0x3002: return "attribute transmission too short";
        case 0x3003: return "attribute transmission too long";
        case 0x3004: return "attribute cannot be changed (read only)";
        case 0x3005: return "attribute is write-protected at this time";
        case 0x4001: return "no unit";
        case 0x5001: return "no minimum input value";
        case 0x6001: return "no maximum input value";
        case 0x7002: return "operation data transmission too short";
        case 0x7003: return "operation data transmission too long";
        case 0x7004: return "operation data cannot be changed (read only)";
        case 0x7005: return "operation data is write-protected at this time";
        case 0x7006: return "operation data is smaller than the minimum input value";
        case 0x7007: return "operation data is greater than the maximum input value";
        case 0x7008: return "invalid operation data";
        case 0x7009: return "operation data is write-protected by a password";
        case 0x700A: return "operation data is write-protected (configured cyclically)";
        case 0x7010: return "procedure command already active";
        case 0x7011: return "procedure command not interruptible";
        case 0x7012: return "procedure command not executable at this time";
        case 0x7013: return "procedure command not executable (invalid or false parameters)";
        case 0x8001: return "no default value";
        case 0x800A: return "invalid drive number";
        case 0x800B: return "general error";
        case 0x800C: return "no element addressed";
        default: return "unknown SoE error";
    }
}

}  // namespace ecpair::wire
