// Fuzz target: a mailbox message as a slave or master might put it in a
// sync manager: header, CoE header, SDO in both directions. Decoded SDO
// messages must re-encode without writing past their own size.

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/mailbox.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const ecpair::ConstBytes in(data, size);
    const auto header = ecpair::wire::MailboxHeader::decode(in);
    if (!header) return 0;
    const auto body = in.subspan(ecpair::wire::MailboxHeader::kSize, header->length);
    if (header->type == ecpair::wire::MailboxType::Error) {
        (void)ecpair::wire::MailboxErrorReply::decode(body);
        return 0;
    }
    const auto coe = ecpair::wire::CoeHeader::decode(body);
    if (!coe) return 0;
    for (const bool response : {false, true}) {
        const auto sdo = ecpair::wire::SdoMessage::decode(body.subspan(ecpair::wire::CoeHeader::kSize), response);
        if (!sdo) continue;
        std::vector<std::uint8_t> out(sdo->encoded_size() + 1, 0xA5);
        sdo->encode(ecpair::Bytes(out.data(), sdo->encoded_size()));
        if (out.back() != 0xA5) std::abort();
    }
    return 0;
}
