#pragma once
// What an EscDescription means for the hardware and the slave stack, worked
// out once per ESC:
//
//  - the SyncManager plan: role, start, length, control byte and enable flag
//    of SM0..SM7 as the SII SM category advertises them and as the AL state
//    machine checks them. The mailbox SMs come from the ENI <Mailbox> (SM0 =
//    Send, SM1 = Recv) or from <Sm0>/<Sm1> of type MBoxOut/MBoxIn; process
//    data SMs from <SmN> of type Outputs/Inputs. The expected size of a
//    process data SM is the sum of the PDOs assigned to it (a PDO's Sm
//    attribute or the SM's Pdo list), rounded up to bytes; without assigned
//    PDOs it is unknown and any size is accepted;
//    The SyncManager records the ENI's InitCmds write come last and win
//    (start, control byte, enable; the length of a mailbox SM, or of a
//    process data SM without assigned PDOs): the configurator wrote them
//    from the device's ESI, which is what a real slave checks against;
//  - the PDOs the SII lists (the assigned ones), the mailbox areas and
//    protocols, the process RAM size (at least 8 KiB, enough for every
//    described buffer, three times for a buffered SM) and the ports;
//  - whether the ESC runs in device emulation (docs/ECSIM.md "Device
//    emulation"): a slave without a mailbox whose process data SMs are all
//    digital I/O buffers (outputs within 0x0F00-0x0F03, inputs within
//    0x1000-0x1003) has no microcontroller, like an EL1xxx/EL2xxx terminal.
//    Slaves without any process data SM (couplers) keep the stack model,
//    which checks nothing for them (see the doc for why).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/eni/model.hpp"
#include "ecpair/sim/esc.hpp"

namespace ecpair::sim {

// Values are the SII SyncManager type codes.
enum class SmRole : std::uint8_t { Unused = 0, MailboxOut = 1, MailboxIn = 2, Outputs = 3, Inputs = 4 };

struct SmPlan {
    SmRole role = SmRole::Unused;
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    bool enable = false;
    std::optional<std::uint16_t> expected_size;  // process data SMs with assigned PDOs
};

// A mailbox pair: `out` is written by the master (SM0), `in` read by it (SM1).
struct MailboxAreas {
    eni::MailboxArea out;
    eni::MailboxArea in;
};

struct AssignedPdo {
    const eni::Pdo* pdo = nullptr;
    std::uint8_t sm = 0;
    bool inputs = false;  // a TxPDO
};

struct EscLayout {
    static constexpr int kSmCount = 8;

    std::array<SmPlan, kSmCount> sms{};
    int described_sm_count = 0;  // SM0..SM(n-1) appear in the SII
    std::optional<MailboxAreas> mailbox;
    std::optional<MailboxAreas> bootstrap;
    std::uint16_t mailbox_protocols = 0;  // SII word 0x1C bits
    bool mailbox_data_link_layer = false;
    std::vector<AssignedPdo> pdos;
    int output_sm = 2;  // where the slave application finds outputs / puts inputs
    int input_sm = 3;
    std::size_t ram_bytes = 8 * 1024;
    int port_count = 2;
    std::array<char, 4> port_physics{};  // 'Y', 'K' or 0 for a port that is not implemented
    bool device_emulation = false;       // AL status follows AL control, no stack (0x0141 b0)

    static EscLayout of(const EscDescription& description);

    bool has_mailbox() const { return mailbox.has_value(); }
    std::uint8_t port_descriptor() const;  // register 0x0007
};

// Default SyncManager control byte for a role (SOES options.h: 0x26, 0x22, 0x64, 0x20).
std::uint8_t default_sm_control(SmRole role);

}  // namespace ecpair::sim
