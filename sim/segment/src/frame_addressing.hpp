#pragma once
// Which slaves a frame's datagrams may address, read once per frame, and
// what the slaves the frame passes unaddressed would have done to it.
//
// The segment's fast pass (segment_carry.cpp) carries a frame past an ESC
// without calling it when addresses() says no datagram of the frame can
// address that ESC. What such an ESC does to a frame (PassDigest) is written
// into the frame without it: every EPU adds 1 to the ADP of the APxx
// datagrams, so before an ESC processes the frame (and when it leaves) their
// ADP is set from the number of EPUs passed; the IRQ fields (OR) and the
// source MAC's forwarding bit do not depend on the order, so passed() gathers
// them and apply_passed() writes them once.
//
// addresses() may say yes too often, never too rarely: the digests it reads
// are conservative (the alias matches even when not enabled, an FMMU range
// may cover more than its FMMUs). A datagram that addresses every slave
// (BRD, BWR, BRW, ARMW, FRMW) makes every ESC on the route process the frame
// (it still follows the route: no step machine); a frame with more datagrams
// of a kind than are kept here is not summarised: it takes the step machine.

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecpair/sim/esc.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::sim::detail {

class FrameAddressing {
public:
    // False: the frame takes the step machine (see above).
    bool summarise(const wire::FrameView& frame);
    // Whether a datagram may address the ESC of `digest`; `epu_pass` is the
    // number of EPUs the frame passed before this one (what APxx counts).
    bool addresses(const PassDigest& digest, std::uint32_t epu_pass) const;
    // Whether the ESC of `digest`, processing the frame, needs to know where
    // the frame arrived: a datagram may write its DL control (0x0100, the
    // loop settings take the entry port) or its DC latch (0x0900, the receive
    // times). Otherwise the arrivals of a frame at its ports change nothing
    // in a passable ESC and are left out.
    bool needs_arrivals(const PassDigest& digest) const {
        return writes_arrival_registers_ || (writes_logically_ && digest.fmmu_maps_registers);
    }
    // ADP of the APxx datagrams as after `epus` EPUs.
    void set_auto_increment(wire::FrameView& frame, std::uint32_t epus) const;
    // The frame passed this ESC's EPU without being processed.
    void passed(const PassDigest& digest) {
        passed_irq_ = static_cast<std::uint16_t>(passed_irq_ | digest.irq);
        passed_forwarding_bit_ = passed_forwarding_bit_ || digest.forwarding_rule;
    }
    void forget_passed() {
        passed_irq_ = 0;
        passed_forwarding_bit_ = false;
    }
    // Writes what the passed ESCs did to the IRQ fields and the source MAC.
    void apply_passed(wire::FrameView& frame) const;

private:
    static constexpr std::size_t kKept = 16;
    struct LogicalRange {
        std::uint64_t begin;
        std::uint64_t end;
    };

    std::array<std::uint16_t, kKept> auto_increment_{};  // ADP of APxx as the frame entered
    std::size_t auto_increment_count_ = 0;
    std::array<std::uint16_t, kKept> configured_{};  // ADP of FPxx
    std::size_t configured_count_ = 0;
    std::array<LogicalRange, kKept> logical_{};  // bytes of Lxx
    std::size_t logical_count_ = 0;
    bool every_ = false;  // a datagram addresses every slave
    bool writes_arrival_registers_ = false;  // a physical write may reach 0x0100-0x0103 or 0x0900-0x0903
    bool writes_logically_ = false;          // an LWR or LRW

    std::uint16_t passed_irq_ = 0;
    bool passed_forwarding_bit_ = false;
};

}  // namespace ecpair::sim::detail
