#pragma once
// The EtherCAT mailbox (ETG.1000.4/.6): every mailbox message in SM0/SM1
// starts with a 6-byte header:
//   Length (2)   bytes of the message after this header
//   Address (2)  station address of the source (slave->master) or 0
//   byte 4       [5:0] channel, [7:6] priority
//   byte 5       [3:0] type, [6:4] counter (1..7, 0 = not used), [7] reserved

#include <cstdint>
#include <optional>
#include <string_view>

#include "ecpair/common/bytes.hpp"

namespace ecpair::wire {

enum class MailboxType : std::uint8_t { Error = 0, AoE = 1, EoE = 2, CoE = 3, FoE = 4, SoE = 5, VoE = 15 };

struct MailboxHeader {
    static constexpr std::size_t kSize = 6;

    std::uint16_t length = 0;
    std::uint16_t address = 0;
    std::uint8_t channel = 0;
    std::uint8_t priority = 0;
    MailboxType type = MailboxType::CoE;
    std::uint8_t counter = 0;

    void encode(Bytes out) const;
    // nullopt when fewer than kSize bytes or the declared length runs past `in`.
    static std::optional<MailboxHeader> decode(ConstBytes in);
    friend bool operator==(const MailboxHeader&, const MailboxHeader&) = default;
};

// The master learns that a slave has written its mailbox from the status byte
// of SM1 (the slave-to-master mailbox, 0x0800 + 8 + 5): bit 3, mailbox full.
inline constexpr std::uint16_t kSm1StatusRegister = 0x080D;
inline constexpr std::uint8_t kSmStatusMailboxFull = 0x08;

// The next mailbox counter after `counter` (1..7, wrapping; 0 is never used).
inline std::uint8_t next_mailbox_counter(std::uint8_t counter) {
    return static_cast<std::uint8_t>(counter >= 7 ? 1 : counter + 1);
}

// Mailbox error reply (type 0): service 1, detail code.
struct MailboxErrorReply {
    static constexpr std::size_t kSize = 4;
    std::uint16_t detail = 0;  // 1 syntax, 2 unsupported protocol, 3 invalid channel, 4 service not supported,
                               // 5 invalid header, 6 size too short, 7 no more memory, 8 invalid size
    void encode(Bytes out) const;
    static std::optional<MailboxErrorReply> decode(ConstBytes in);
};

std::string_view mailbox_error_text(std::uint16_t detail);

}  // namespace ecpair::wire
