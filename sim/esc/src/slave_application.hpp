#pragma once
// A small application on the PDI side so that process data visibly flows.
// After every frame that addressed the ESC, in SAFEOP and OP:
//
//   inputs[0..1]  a free-running 16-bit counter (little-endian), +1 per such frame
//   inputs[2..]   OP: a copy of the outputs, as far as both fit;
//                 SAFEOP: zeros (outputs are not applied in SAFEOP)
//
// An input SyncManager of less than 2 bytes gets the mirrored outputs only.
// A single-buffered (mailbox-mode) SyncManager works as a drive's firmware
// works it: the inputs are written when the master has read the last ones
// (the buffer is empty) and the buffer is then marked full, so the next
// LRD reads them (a TwinCAT export for an Omron drive has its inputs on SM3
// with control byte 0x22); outputs the master wrote into a full one are
// taken and the buffer emptied for the next LWR. The counter then counts
// the buffers written.
// A slave identified by an input word shows its value at that address of the
// input buffer on top of all that.
// "Outputs" and "inputs" are the buffers of the first Outputs and Inputs
// SyncManagers of the description (SM2/SM3 when it names none), as the
// master configured them; a SyncManager that is disabled, deactivated or
// outside the process RAM is left alone. The counter restarts at 0 on
// power-on, so a given frame sequence always gives the same inputs.

#include <cstdint>

#include "al_state_machine.hpp"
#include "esc_layout.hpp"
#include "esc_memory.hpp"
#include "sync_manager.hpp"

namespace ecpair::sim {

class SlaveApplication {
public:
    SlaveApplication(EscMemory& memory, SyncManagerUnit& sync_managers, const EscLayout& layout);

    void reset() { counter_ = 0; }
    // Input-word identification: `value` at ESC address `address`, when it
    // lies in the input buffer (written after the counter and the mirror).
    void show_word(std::uint16_t address, std::uint16_t value) {
        word_address_ = address;
        word_value_ = value;
    }
    void after_frame(AlState state);

private:
    bool usable(const SmChannel& channel, bool ecat_writes) const;

    EscMemory& memory_;
    SyncManagerUnit& sync_managers_;
    int output_sm_;
    int input_sm_;
    std::uint16_t counter_ = 0;
    std::uint16_t word_address_ = 0;  // 0: no identification word
    std::uint16_t word_value_ = 0;
};

}  // namespace ecpair::sim
