#pragma once
// The demo applications ecpaird can run as its cycle hook, so that data flow
// is visible without a user program:
//
//  - WalkingBit: output byte i of every slave holds 1 << ((step + i) % 8),
//    the step advancing every `step_cycles` cycles.
//  - LoopbackCheck: WalkingBit, and in OP a check that every slave's inputs
//    echo its outputs the way ecsim's slaves do it (inputs[0..1] are a
//    counter, inputs[2..] a copy of the outputs; see docs/ESC_EMULATION.md).
//    The echo may lag one cycle (LRW reads before it writes), so the
//    current and the previous outputs are both accepted; a cycle is only
//    checked when the one before it was complete too, i.e. when that cycle's
//    outputs are known to have reached the slaves (after a lost output frame
//    the slaves echo older outputs, which is no error of the data path), and
//    never in the first two cycles after this master (again) sends: while it
//    stood by, the outputs it remembers are not the ones the slaves had.
//    The first mismatches are logged with the cycle, the slave and the bytes.

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "ecpair/config/daemon_settings.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/master.hpp"

namespace ecpair::daemon {

struct LoopbackStats {
    std::uint64_t cycles_checked = 0;
    std::uint64_t mismatches = 0;  // slave checks that matched neither the current nor the previous outputs
    std::uint64_t slaves_checked = 0;
};

class DemoApplication {
public:
    DemoApplication(const eni::EniConfig& eni, config::DemoKind kind, std::uint32_t step_cycles);

    void on_cycle(master::ProcessImage& image, const master::CycleInfo& info);
    // Any thread (the operator service reads it while the cycle runs).
    LoopbackStats stats() const;
    std::size_t checked_slaves() const { return checks_.size(); }

private:
    struct SlaveArea {
        std::uint32_t output_offset;
        std::uint32_t output_length;
    };
    struct LoopbackCheck {
        std::uint32_t output_offset;
        std::uint32_t input_offset;  // where the copy of the outputs starts (after the counter)
        std::uint32_t length;
        std::string slave;           // the ENI's name and station address, for the log
    };

    void write_outputs(master::ProcessImage& image, std::uint64_t cycle);
    bool matches(const master::ProcessImage& image, const LoopbackCheck& check, ConstBytes outputs) const;
    void report_mismatch(const master::ProcessImage& image, const LoopbackCheck& check, std::uint64_t cycle) const;

    config::DemoKind kind_;
    std::uint32_t step_cycles_;
    std::vector<SlaveArea> outputs_;
    std::vector<LoopbackCheck> checks_;
    std::vector<std::uint8_t> previous_outputs_;
    bool previous_inputs_valid_ = false;
    // Written by the cycle thread only, read by any: relaxed atomics.
    struct AtomicStats {
        std::atomic<std::uint64_t> cycles_checked{0}, mismatches{0}, slaves_checked{0};
    } stats_;
};

}  // namespace ecpair::daemon
