#pragma once
// Turns the cyclic plan into frames every cycle and their returns into the
// input image: fills each datagram's written data from the output image,
// copies each datagram's read data into the input image, and checks every
// working counter the ENI gives (<Cnt>) -- as corrected for the slaves on
// the bus now (Hot-Connect: an absent group does not answer), and only from
// the state the datagram can be right in (PlannedDatagram::valid_from). Nothing is
// allocated per cycle: the per-state datagram lists are computed at
// construction.
//
// Datagrams are numbered flat, frame by frame in plan order (flat_index);
// that numbering is how corrected WKCs and the last WKCs received are given.

#include <array>
#include <optional>
#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::master {

struct WkcMismatch {
    std::uint16_t frame = 0;
    const PlannedDatagram* datagram = nullptr;
    std::uint16_t expected = 0;
    std::uint16_t received = 0;
};

struct FrameCompletion {
    bool layout_ok = true;   // the returned frame matched what was sent
    std::uint16_t datagrams = 0;
    std::uint16_t wkc_errors = 0;
};

class CyclicExchange {
public:
    explicit CyclicExchange(CyclicPlan plan);

    const CyclicPlan& plan() const { return plan_; }
    std::size_t frame_count() const { return plan_.frames.size(); }
    // Whether frame `index` has any datagram to send in `state`.
    bool active(std::size_t index, eni::SlaveState state) const;

    // Writes frame `index` for `state` into `buffer` (Ethernet header given by
    // the caller) and returns its bytes. Remembers the state for completion.
    Bytes build(std::size_t index, eni::SlaveState state, ConstBytes outputs, const wire::EthernetHeader& ethernet,
                Bytes buffer);

    // Whether every datagram of a returned frame that has an expected WKC got
    // exactly it (false when none has one).
    bool counters_complete(std::size_t index, const wire::ConstFrameView& returned) const;

    // Applies a returned (merged) frame: read data -> inputs, WKC checks.
    // Mismatches are appended to `mismatches` up to its capacity.
    FrameCompletion complete(std::size_t index, const wire::ConstFrameView& returned, Bytes inputs,
                             std::vector<WkcMismatch>& mismatches);

    std::size_t flat_index(std::size_t frame, std::size_t datagram) const { return first_[frame] + datagram; }
    std::size_t datagram_count() const { return expected_.size(); }
    // The expected WKC of every datagram (flat); no allocation (the size is fixed).
    void set_expected(const std::vector<std::optional<std::uint16_t>>& expected);
    std::optional<std::uint16_t> expected(std::size_t flat) const { return expected_[flat]; }
    // The WKC a datagram came back with last (0 before it ever did).
    std::uint16_t last_wkc(std::size_t flat) const { return last_wkc_[flat]; }
    // The IRQ fields of the frames as they came back last, ORed (the slaves' ECAT events).
    std::uint16_t irq() const;

private:
    static std::size_t state_slot(eni::SlaveState state);

    CyclicPlan plan_;
    // active_[frame][state slot] = indices of the frame's datagrams sent in that state.
    std::vector<std::array<std::vector<std::uint16_t>, 3>> active_;
    std::vector<std::size_t> last_state_slot_;
    std::vector<std::size_t> first_;  // flat index of each frame's first datagram
    std::vector<std::optional<std::uint16_t>> expected_;
    std::vector<std::uint16_t> last_wkc_;
    std::vector<std::uint16_t> frame_irq_;  // per frame
};

}  // namespace ecpair::master
