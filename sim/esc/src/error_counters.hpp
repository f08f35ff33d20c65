#pragma once
// Error counters 0x0300-0x0313 (datasheet II §2.9). Counters stop at 0xFF.
//
//  - 0x0300 + 2p invalid frames and 0x0301 + 2p RX errors of port p: a frame
//    the port's PHY received with an error (`ecsim ctl port-errors`, a cable
//    impairment) counts in both at the port that received it damaged;
//  - 0x0308 + p forwarded RX errors: a frame an ESC upstream already counted
//    and marked, counted again at each port it reaches later;
//    a write to any of 0x0300-0x030B clears all twelve;
//  - 0x030C processing unit errors: counts circulating frames destroyed at a
//    closed port 0; a write clears it;
//  - 0x030D PDI errors (stays 0); a write clears it;
//  - 0x0310-0x0313 lost links per port (an open port in Auto mode lost its
//    link); a write to any of them clears them all.
//  - 0x0442/0x0443 watchdog counters, cleared by a write.

#include "esc_memory.hpp"

namespace ecpair::sim::error_counters {

void count_processing_unit_error(EscMemory& memory);
void count_lost_link(EscMemory& memory, int port);
// A damaged frame reached `port`: an invalid frame and an RX error when this
// ESC is the first to see the damage, a forwarded RX error when an ESC
// upstream marked it already.
void count_received_error(EscMemory& memory, int port, bool marked_upstream);
// After the master's writes were committed: clears what it wrote to.
void apply_clearing_writes(EscMemory& memory);

}  // namespace ecpair::sim::error_counters
