#pragma once
// The ECAT view of an ESC's address space: what one datagram's read or write
// of [address, address + n) does, byte range by byte range.
//
//  - registers (below 0x0F80): reads return the effective value (the DC
//    unit first computes what it shows at that moment); writes are
//    staged in the shadow buffer until the frame ends. Reading DL status or
//    AL status clears its ECAT event bit (0x0210 b2 / b3). Reserved
//    registers read as 0 and ignore writes, but are accessible (they count
//    for the WKC);
//  - user and process RAM: direct, under the SyncManagers' control;
//  - beyond the process RAM (or all process RAM while the SII configuration
//    has not been loaded): not accessible, not counted.
//
// read()/write() return whether at least one byte was accessed, which is what
// the working counter needs.

#include <cstddef>
#include <cstdint>

#include "ecpair/common/bytes.hpp"
#include "esc_memory.hpp"
#include "sync_manager.hpp"

namespace ecpair::sim {

// Reads either copy memory into the datagram or OR it in (BRD/BRW).
enum class ReadMode : std::uint8_t { Copy, Or };

// Registers whose value is computed when a frame reads them (the DC unit's
// system time and next SYNC pulses): told before a read of the DC range.
class ComputedRegisters {
public:
    virtual void before_read(std::uint32_t begin, std::uint32_t end) = 0;

protected:
    ~ComputedRegisters() = default;
};

class PhysicalAccess {
public:
    PhysicalAccess(EscMemory& memory, SyncManagerUnit& sync_managers);

    // The process RAM answers only once the SII configuration is loaded.
    void set_process_ram_available(bool available) { process_ram_available_ = available; }
    // Who computes the DC registers before they are read (null: nobody).
    void set_computed_registers(ComputedRegisters* computed) { computed_ = computed; }

    bool read(std::uint32_t address, Bytes out, ReadMode mode);
    bool write(std::uint32_t address, ConstBytes in);
    // The byte a bit-wise write in this frame starts from (staged registers included).
    std::uint8_t pending_value(std::uint16_t address) const { return memory_.pending_value(address); }

private:
    void read_registers(std::uint32_t address, Bytes out, ReadMode mode);
    bool read_ram(std::uint32_t address, Bytes out, ReadMode mode);
    bool write_ram(std::uint32_t address, ConstBytes in);
    std::uint32_t ram_end() const;

    EscMemory& memory_;
    SyncManagerUnit& sync_managers_;
    bool process_ram_available_ = true;
    ComputedRegisters* computed_ = nullptr;
};

}  // namespace ecpair::sim
