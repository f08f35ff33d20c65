#pragma once
// The receiving side of the Cyclic Master Red Frame. The INACTIVE feeds it
// the datagrams of every frame it forwards (the mirror), the ACTIVE those of
// its returned CMF (to read the INACTIVE's MASTER_PD_IN). Parts are placed by
// their segment headers, in any order, and a copy of a part already held
// (the MAIN and the RED copy of the same frame) is recognised and skipped.
// When every part of a cycle is in, feed() says Completed and content()
// shows that cycle until the next one completes.
//
// The assembler is made for the layout we expect (our ENI and parameters):
// everything is checked against that plan, so a hostile or foreign datagram
// can neither make it allocate nor place bytes outside a section. A partner
// with other parameters is refused (PartnerDiffers) and its header kept in
// last_header(), so that the caller can name what differs.
//
// Not thread-safe: the caller serialises feed() and the accessors.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/wire/datagram.hpp"

namespace ecpair::redundancy {

class CmfAssembler {
public:
    enum class Outcome : std::uint8_t {
        NotCmf,     // not addressed to ADP 0 / ADO 0x4155 with a NOP: not ours
        Stored,     // a new part of the cycle being assembled
        Duplicate,  // a part already held (or of the cycle already completed)
        Stale,      // a part of a cycle older than the one being assembled
        Completed,  // this part completed its cycle: content() shows it
    };

    // The lowest WKC among the parts of the completed cycle as they were
    // stored: what the INACTIVE read (+2 each) and wrote (+1, MASTER_PD_IN and STANDBY_STATUS).
    struct WorkingCounters {
        std::uint16_t lowest_read = 0;
        std::optional<std::uint16_t> lowest_write;  // of the sections the INACTIVE writes
    };

    struct Counters {
        std::uint64_t completed = 0;
        std::uint64_t abandoned = 0;  // cycles left incomplete when a newer cycle began
        std::uint64_t duplicates = 0;
        std::uint64_t stale = 0;
        std::uint64_t errors = 0;
    };

    // A part this many cycles older than the one being assembled is stale; a
    // part further back means the partner's cycle counter restarted, and
    // begins a new cycle.
    static constexpr std::int32_t kStaleWindow = 8;

    explicit CmfAssembler(CmfPlan expected);

    Expected<Outcome, CmfError> feed(const wire::ConstDatagramView& datagram);
    Expected<Outcome, CmfError> feed(const wire::DatagramView& datagram) {
        return feed(wire::ConstDatagramView(datagram.bytes(), datagram.frame_offset()));
    }

    const CmfPlan& plan() const { return plan_; }
    // Whether a cycle has completed yet; the three accessors below need one.
    bool has_complete() const { return has_complete_; }
    const CmfHeader& header() const { return complete_.header; }
    const CmfContent& content() const { return content_; }
    const WorkingCounters& working_counters() const { return complete_.wkc; }

    // The last HEADER that decoded, also one refused as PartnerDiffers or LayoutMismatch.
    const std::optional<CmfHeader>& last_header() const { return last_header_; }
    const Counters& counters() const { return counters_; }

private:
    // One cycle's bytes: the sections back to back, and what was decoded from them.
    struct CycleBuffers {
        std::vector<std::uint8_t> sections;
        std::vector<master::SlaveStateEntry> slaves;
        CmfHeader header;
        WorkingCounters wkc;
    };

    Expected<void, CmfError> check_header(const CmfSegmentHeader& segment, ConstBytes payload,
                                          std::size_t payload_offset);
    Expected<void, CmfError> check_placement(const CmfSegmentHeader& segment, std::size_t payload_length,
                                             std::size_t data_offset) const;
    Outcome place(const CmfSegmentHeader& segment, ConstBytes payload, std::uint16_t wkc);
    void begin_cycle(std::uint32_t cycle_low);
    void finish_cycle();
    ConstBytes section(const CycleBuffers& buffers, CmfKind kind) const;
    Expected<Outcome, CmfError> fail(const CmfError& error);

    CmfPlan plan_;
    std::array<std::size_t, kCmfKinds.size() + 1> section_offset_{};  // indexed by CmfKind value
    CycleBuffers assembling_;
    CycleBuffers complete_;
    CmfContent content_;  // points into complete_
    bool has_complete_ = false;

    std::optional<std::uint32_t> cycle_low_;  // the cycle being assembled (or just completed)
    bool cycle_done_ = false;
    std::vector<std::uint8_t> received_;  // per part of the plan: 1 once stored
    std::size_t received_count_ = 0;

    std::optional<CmfHeader> last_header_;
    Counters counters_;
};

}  // namespace ecpair::redundancy
