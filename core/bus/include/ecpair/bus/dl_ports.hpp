#pragma once
// The port bits of DL status (0x0110, esc-facts.md §2): per port p, bit 4+p
// physical link, bit 8+2p loop closed, bit 9+2p communication established.
// A port leads downstream (to another slave, or to the master's RED side)
// when it has link and its loop is open. Bus topology is read from these
// bits: a frame visits a slave's ports in the order 0 -> EPU -> 3 -> 1 -> 2,
// so the slave at the next position hangs on the first such port, and so on
// depth first.

#include <cstdint>

namespace ecpair::bus {

struct DlPorts {
    std::uint16_t raw = 0;

    bool link(int port) const { return (raw & (1u << (4 + port))) != 0; }
    bool loop_closed(int port) const { return (raw & (1u << (8 + 2 * port))) != 0; }
    bool downstream(int port) const { return link(port) && !loop_closed(port); }
};

}  // namespace ecpair::bus
