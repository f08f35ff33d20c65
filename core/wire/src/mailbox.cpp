#include "ecpair/wire/mailbox.hpp"

namespace ecpair::wire {

void MailboxHeader::encode(Bytes out) const {
    store_le<std::uint16_t>(out, 0, length);
    store_le<std::uint16_t>(out, 2, address);
    out[4] = static_cast<std::uint8_t>((channel & 0x3F) | ((priority & 0x03) << 6));
    out[5] = static_cast<std::uint8_t>((static_cast<std::uint8_t>(type) & 0x0F) | ((counter & 0x07) << 4));
}

std::optional<MailboxHeader> MailboxHeader::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    MailboxHeader h;
    h.length = load_le<std::uint16_t>(in, 0);
    h.address = load_le<std::uint16_t>(in, 2);
    h.channel = static_cast<std::uint8_t>(in[4] & 0x3F);
    h.priority = static_cast<std::uint8_t>(in[4] >> 6);
    h.type = static_cast<MailboxType>(in[5] & 0x0F);
    h.counter = static_cast<std::uint8_t>((in[5] >> 4) & 0x07);
    if (kSize + h.length > in.size()) return std::nullopt;
    return h;
}

void MailboxErrorReply::encode(Bytes out) const {
    store_le<std::uint16_t>(out, 0, 0x0001);  // service: mailbox error
    store_le<std::uint16_t>(out, 2, detail);
}

std::optional<MailboxErrorReply> MailboxErrorReply::decode(ConstBytes in) {
    if (in.size() < kSize || load_le<std::uint16_t>(in, 0) != 0x0001) return std::nullopt;
    return MailboxErrorReply{load_le<std::uint16_t>(in, 2)};
}

std::string_view mailbox_error_text(std::uint16_t detail) {
    switch (detail) {
        case 1: return "syntax error in the mailbox header";
        case 2: return "mailbox protocol not supported";
        case 3: return "invalid channel";
        case 4: return "service not supported";
        case 5: return "invalid mailbox header";
        case 6: return "mailbox data too short";
        case 7: return "no more memory";
        case 8: return "inconsistent mailbox size";
        default: return "unknown mailbox error";
    }
}

}  // namespace ecpair::wire
