#pragma once
// Distributed clocks registers (datasheet II §2.15, esc-facts.md §2).
//
// The local clock of the emulated ESC is the simulation time in ns. Then:
//  - 0x0910 (64 bit) reads as local time + system time offset (0x0920),
//    taken when the frame starts through the processing unit;
//  - a master write to 0x0910 (ARMW/FRMW distributing the reference time, or
//    a plain write) is compared, not stored: the difference between the
//    local copy and the written time plus the system time delay (0x0928) is
//    put into 0x092C (bit 31 set when the local copy is behind, bits 30:0 the
//    magnitude). A 4-byte write compares the low 32 bits only;
//  - a write to 0x0900 latches the receive time of that frame at every port:
//    port 0 (0x0900) and the processing unit (0x0918, 64 bit) at once, the
//    other ports (0x0904 + 4(n-1)) when the frame passes them, as the segment
//    reports through port_arrival(). Ports the frame passed before reaching
//    the processing unit (port 0 closed) are latched from their last arrival;
//  - activation (0x0980/0x0981), start time (0x0990) and cycle times (0x09A0)
//    are plain registers.

#include <array>
#include <cstdint>

#include "ecpair/sim/esc.hpp"
#include "esc_memory.hpp"

namespace ecpair::sim {

class DcUnit {
public:
    explicit DcUnit(EscMemory& memory);

    void reset();
    // The frame enters the processing unit: the system time copy for reads.
    void start_of_frame(std::uint64_t time_ns);
    // A frame reached `port` from outside.
    void port_arrival(int port, std::uint64_t time_ns, std::uint64_t frame_seq);
    // End of a frame that wrote 0x0900: latch its receive times.
    void latch_receive_times(std::uint64_t frame_seq, std::uint64_t epu_time_ns);
    // End of a frame that wrote 0x0910: feed the comparison.
    void system_time_written(std::uint64_t time_ns);

private:
    struct Arrival {
        std::uint64_t time_ns = 0;
        std::uint64_t frame_seq = 0;
        bool valid = false;
    };

    void latch_port(int port, std::uint64_t time_ns);

    EscMemory& memory_;
    std::array<Arrival, kMaxPorts> arrivals_{};
    std::uint64_t latch_seq_ = 0;
    bool latch_pending_ = false;
};

}  // namespace ecpair::sim
