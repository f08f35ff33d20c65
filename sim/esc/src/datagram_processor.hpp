#pragma once
// What one ESC's processing unit does to one datagram (esc-facts.md §1;
// datasheet I tables 5-7):
//
//  - addressing: APxx/ARMW address the slave that receives ADP 0 and every
//    slave increments ADP; BRD/BWR/BRW address every slave, which also
//    increment ADP; FPxx/FRMW match the station address (0x0010) or, when
//    0x0100 b24 is set, the station alias (0x0012); Lxx go through the FMMUs;
//    NOP and reserved commands are left alone;
//  - data: reads copy memory into the datagram (BRD/BRW OR it in); the
//    read-write commands read first, then write the data as it arrived, to
//    ADO + the read/write offset register (0x0108); ARMW/FRMW read on the
//    addressed slave and write on all others;
//  - WKC: +1 for a read, +1 for a write, +1/+2/+3 for the read-write
//    commands, +1 for ARMW/FRMW, when at least one byte (bit) was accessed;
//  - IRQ: (ECAT event request 0x0210 AND mask 0x0200) is ORed into every
//    datagram.
//
// A datagram addresses the ESC when its addressing selects it (ADP 0, the
// station address or alias, every slave for BRD/BWR/BRW/ARMW/FRMW) or, for
// Lxx, when an active FMMU maps one of its logical bytes; one that does not
// leaves the ESC as it was.
//
// What the DC unit needs to know of the datagrams (DcFrameAccess) is noted
// on the way: a BWR/FPWR to 0x0900 (the ports' receive times latch only for
// those), an ARMW/FRMW that read 0x0910 here (this ESC is the reference).

#include <array>
#include <cstdint>

#include "dc_registers.hpp"
#include "ecpair/wire/datagram.hpp"
#include "esc_memory.hpp"
#include "fmmu.hpp"
#include "physical_access.hpp"

namespace ecpair::sim {

class DatagramProcessor {
public:
    DatagramProcessor(EscMemory& memory, PhysicalAccess& physical, FmmuUnit& fmmus);

    // True when the datagram addressed this ESC (see above).
    bool process(const wire::DatagramView& datagram);
    // What the frame's datagrams did to the DC unit; cleared for the next frame.
    DcFrameAccess take_dc_access() {
        const DcFrameAccess access = dc_access_;
        dc_access_ = {};
        return access;
    }

private:
    enum class Access : std::uint8_t { Read, BroadcastRead, Write, ReadWrite, BroadcastReadWrite, ReadOrWrite };

    bool configured_address_matches(std::uint16_t adp) const;
    std::uint16_t physical_access(const wire::DatagramView& datagram, Access access, bool addressed);
    std::uint16_t logical_access(const wire::DatagramView& datagram);

    EscMemory& memory_;
    PhysicalAccess& physical_;
    FmmuUnit& fmmus_;
    DcFrameAccess dc_access_;
    // The data of a read-write datagram as it arrived (the write half uses it).
    std::array<std::uint8_t, 2048> arrived_{};
};

}  // namespace ecpair::sim
