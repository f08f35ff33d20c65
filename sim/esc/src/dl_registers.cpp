// Pure encoders/decoders: the ESC facade keeps the registers themselves.

#include "dl_registers.hpp"

namespace ecpair::sim {

DlControl DlControl::decode(std::uint32_t value) {
    DlControl control;
    control.forwarding_rule = (value & 0x01U) != 0;
    control.temporary = (value & 0x02U) != 0;
    control.loop = decode_loop(static_cast<std::uint8_t>(value >> 8));
    control.alias_enabled = (value & (1U << 24)) != 0;
    return control;
}

std::array<LoopSetting, kMaxPorts> DlControl::decode_loop(std::uint8_t loop_byte) {
    std::array<LoopSetting, kMaxPorts> loop{};
    for (std::size_t p = 0; p < loop.size(); ++p) loop[p] = static_cast<LoopSetting>((unsigned{loop_byte} >> (2 * p)) & 0x03U);
    return loop;
}

std::uint16_t dl_status(const PortLogic& ports, bool pdi_operational) {
    std::uint16_t status = pdi_operational ? 0x0001 : 0x0000;
    status |= 0x0002;  // PDI watchdog reloaded
    for (int p = 0; p < kMaxPorts; ++p) {
        const bool link = ports.implemented(p) && ports.link(p);
        const bool closed = !ports.implemented(p) || ports.loop_closed(p);
        if (link) status = static_cast<std::uint16_t>(status | (1U << (4 + p)));
        if (closed) status = static_cast<std::uint16_t>(status | (1U << (8 + 2 * p)));
        if (link) status = static_cast<std::uint16_t>(status | (1U << (9 + 2 * p)));
    }
    return status;
}

}  // namespace ecpair::sim
