#pragma once
// Error counters 0x0300-0x0313 (datasheet II §2.9). Counters stop at 0xFF.
//
//  - 0x0300-0x030B RX and forwarded RX errors per port: a write to any of
//    them clears them all. The emulated links are error-free, so they only
//    ever read 0 unless written;
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
// After the master's writes were committed: clears what it wrote to.
void apply_clearing_writes(EscMemory& memory);

}  // namespace ecpair::sim::error_counters
