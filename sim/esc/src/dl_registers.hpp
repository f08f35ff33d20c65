#pragma once
// DL control (0x0100-0x0103) and DL status (0x0110-0x0111), datasheet II
// §2.4, esc-facts.md §2:
//
//   DL control  b0 forwarding rule (1: destroy non-EtherCAT frames and set
//               the source MAC's locally administered bit), b1 temporary loop
//               settings (revert after about a second), b9:8 .. b15:14 loop
//               setting of ports 0..3, b18:16 RX FIFO size, b24 alias enable.
//   DL status   b0 PDI operational (SII loaded), b1 PDI watchdog not expired,
//               b7:4 physical link of ports 0..3, then per port a pair
//               (loop closed, communication established): 0x5A for a middle
//               slave, 0x56 for the last one, 0x55 with every port closed.

#include <array>
#include <cstdint>

#include "ecpair/sim/esc.hpp"
#include "port_logic.hpp"

namespace ecpair::sim {

struct DlControl {
    bool forwarding_rule = true;
    bool temporary = false;
    std::array<LoopSetting, kMaxPorts> loop{};
    bool alias_enabled = false;

    static DlControl decode(std::uint32_t value);
    // The loop settings of 0x0101 alone.
    static std::array<LoopSetting, kMaxPorts> decode_loop(std::uint8_t loop_byte);
};

std::uint16_t dl_status(const PortLogic& ports, bool pdi_operational);

}  // namespace ecpair::sim
