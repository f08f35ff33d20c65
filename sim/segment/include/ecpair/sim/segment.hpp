#pragma once
// A simulated EtherCAT segment: a chain (or tree) of emulated ESCs wired as
// the ENI describes, with the master's MAIN and RED sides at its ends.
//
// carry() moves one frame through the segment exactly as the wire would:
// in at a side, from port to port in each ESC's processing order, through
// the processing unit on the port-0 leg, over the cables of open ports, out
// at a side (or lost, or destroyed). Faults (power, cut cables, a side's
// carrier, an unknown slave spliced in, alias and ID changes) are methods
// here; positions are 1-based, as operators count slaves.
//
// Not thread-safe: one thread (ecsim's event loop, or a test) drives it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sim/esc.hpp"
#include "ecpair/sim/topology.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::sim {

namespace detail {
class DcWatch;
struct FastPass;
class FrameRoute;
struct RouteStep;
struct WalkState;
struct WalkResult;
// A frame's state as the ESCs see it: whole; damaged on its way into the
// port it reaches next (not counted yet); or counted as invalid by an ESC
// and marked, so that every later port counts it as forwarded.
enum class FrameHealth : std::uint8_t { Intact, Damaged, Marked };
}  // namespace detail

// How long frames take (docs/ESC_EMULATION.md "Distributed clocks"): the
// defaults are a line of ET1100s with 100BASE-TX PHYs and 10 m cables.
struct PropagationOptions {
    // One cable from port to port, the PHYs at both ends included (the
    // datasheet's wire delay t_W): 10 m at 5 ns/m and ~250 ns of PHYs.
    std::uint32_t cable_ns = 300;
    // Through an ESC, from a port (or its processing unit) to the next open
    // port: alongside the processing unit (t_F) and through it (t_P). Equal by
    // default: the difference is ESC-specific (the ESI's, not the ENI's), and
    // the common masters' delay calculation assumes none.
    std::uint32_t forwarding_ns = 300;
    std::uint32_t processing_ns = 300;
};

// The ESCs' oscillators. Each ESC's drift is uniform in +-drift_ppm and its
// local time starts at a power-on somewhere below 2^32 ns, both from the
// seed (the same seed, the same clocks). 25 ppm by default: the crystals
// of ESCs are specified at +-25 ppm, so two slaves differ by up to 50 ppm.
// seed 0: exact clocks that all start at 0 at power-on (the simulation time).
struct ClockOptions {
    std::uint32_t drift_ppm = 25;
    std::uint64_t seed = 1;
};

// How a frame enters the segment: whole, or damaged on the cable it came in
// by (a bad cable at a master side: the first port it reaches counts it).
enum class FrameCondition : std::uint8_t { Intact, Damaged };

struct SegmentOptions {
    PropagationOptions propagation;
    ClockOptions clocks;
    // Frames pass the ESCs none of their datagrams address without calling
    // them (see segment_carry.cpp); what a master sees is the same either way.
    // Off: every ESC on the path processes every frame (the reference the
    // tests compare the fast pass with).
    bool fast_pass = true;
};

// A slave of a segment described by hand (tests) or taken from an ENI.
struct SlaveSpec {
    EscDescription esc;
    std::uint16_t phys_addr = 0;
    std::optional<eni::PreviousPort> previous_port;
    int source_line = 0;
    std::size_t group = 0;  // Hot-Connect group number (0: mandatory)
    bool floating = false;  // a floating group's head: not plugged in at first
};

// ecsim's truth about the distributed clocks (Segment::dc_report), for
// `ecsim ctl dc`. The reference clock is the ESC the master uses: the one an
// ARMW/FRMW last read 0x0910 of; before any did (or when that one has no
// power), the first powered ESC with DC by position. A deviation is the
// slave's system time minus the reference's at the same moment of the common
// time base (in 32 bits when either has a 32-bit DC). The figures over
// slaves (max, worst, spread) count the slaves that run SYNC0: those the
// master has synchronised; a slave that is just powered on, or not
// configured, has a deviation but is left out of them.
struct DcSlaveReport {
    std::size_t position = 0;
    bool powered = false;
    DcTruth truth;                          // truth.support None: no DC
    std::optional<std::int64_t> deviation_ns;  // none: no DC, no power or no reference
};

struct DcReport {
    std::uint64_t now_ns = 0;
    std::optional<std::size_t> reference;  // position
    bool reference_from_master = false;    // an ARMW/FRMW read it (else: the first DC slave)
    std::vector<DcSlaveReport> slaves;
    std::size_t synchronised = 0;          // slaves running SYNC0
    std::int64_t max_abs_deviation_ns = 0; // now, over the slaves running SYNC0
    std::int64_t worst_deviation_ns = 0;   // largest absolute deviation since the last reset
    std::optional<std::int64_t> sync0_spread_ns;  // of the latest SYNC0 edge they all passed
    std::uint64_t sync0_missed = 0;        // edges missed or doubled since the last reset
};

struct SideCounters {
    std::uint64_t frames_in = 0;   // frames that entered the segment at this side
    std::uint64_t frames_out = 0;  // frames that left the segment at this side
};

struct SegmentCounters {
    std::array<SideCounters, kSideCount> sides{};
    std::uint64_t destroyed_circulating = 0;  // an EPU destroyed it (circulating bit already set)
    std::uint64_t lost_no_link = 0;           // sent out of a port whose cable is cut, unplugged or dead
    std::uint64_t lost_closed_port = 0;       // reached a port that was closed (e.g. auto-close's closed wait)
    std::uint64_t non_ethercat_dropped = 0;   // destroyed by an EPU's forwarding rule
    std::uint64_t unprocessable = 0;          // EtherType 0x88A4 but not a valid datagram frame: forwarded untouched
    std::uint64_t hop_limit_exceeded = 0;     // still travelling after the hop bound: dropped
    std::uint64_t epus_passed = 0;            // EPUs the fast pass carried a frame past without calling
    // Reached a side damaged (a port error, an impaired cable): the master's
    // NIC drops a frame whose FCS is wrong, so it is not sent.
    std::uint64_t damaged_dropped = 0;
};

// Why a fault request was refused ("position 7 is out of range 1..5").
struct FaultError {
    std::string message;
};

// The vendor ID of the slave insert_unknown_slave() adds: in no ENI.
inline constexpr std::uint32_t kUnknownSlaveVendorId = 0x0BADC0DE;
EscDescription unknown_slave_description();

class Segment {
public:
    // The ENI's slaves in file order, wired by their PreviousPort entries.
    static Expected<Segment, TopologyError> from_eni(const eni::EniConfig& config, SegmentOptions options = {});
    // Slaves described by hand, wired by the same rules as an ENI.
    static Expected<Segment, TopologyError> from_specs(std::vector<SlaveSpec> slaves, SegmentOptions options = {});
    // Slaves and an explicit wiring (Topology::from_cables).
    static Expected<Segment, TopologyError> with_wiring(std::vector<EscDescription> slaves, std::vector<Cable> cables,
                                                        SegmentOptions options = {});

    Segment(Segment&&) noexcept;
    Segment& operator=(Segment&&) noexcept;
    ~Segment();

    // Carries the frame held in buffer[0, size) that enters at `entry` at
    // time `now_ns`. Frames shorter than 60 bytes are first padded with zeros
    // (size grows; the buffer must hold at least 60 bytes). The ESCs change
    // the frame in place. Returns the side it leaves by, or nullopt when it
    // died on the way (see the counters). Allocates nothing (but the first
    // time each side's route is recorded after a change of the slave count).
    // A frame that entered Damaged, or was damaged at a port on its way
    // (inject_rx_errors), is counted by the ESCs' error counters wherever it
    // arrives, processed by no EPU, and never leaves (damaged_dropped).
    std::optional<Side> carry(Side entry, Bytes buffer, std::size_t& size, std::uint64_t now_ns,
                              FrameCondition condition = FrameCondition::Intact);

    // ---- time without frames
    // The ESCs' clocks reached `now_ns` (an expired SM watchdog takes effect
    // even when no frame comes); the earliest moment one of them needs it.
    void advance_time(std::uint64_t now_ns);
    std::optional<std::uint64_t> next_deadline() const;
    // The latest common time the segment has seen (frames and advance_time).
    std::uint64_t now_ns() const { return now_ns_; }

    // ---- distributed clocks (segment_dc.cpp)
    // The truth at now_ns(); allocates (for the control socket, not per frame).
    DcReport dc_report();
    // Starts the worst deviation and the missed-edge count anew.
    void reset_dc_statistics();
    // Test and bench knobs: one ESC's delays and oscillator (positions 1..n).
    Expected<void, FaultError> set_esc_delays(std::size_t position, const EscDelays& delays);
    Expected<void, FaultError> set_oscillator(std::size_t position, const Oscillator& oscillator);

    // ---- faults (positions 1..n)
    // Power: all the slave's ports lose link, so neighbours see link loss;
    // power-on restarts the ESC from its reset state. Repeating is a no-op.
    Expected<void, FaultError> power_off(std::size_t position);
    Expected<void, FaultError> power_on(std::size_t position);
    // Cuts / mends the cable after slave k (0 <= k <= n): k = 0 is the cable
    // entering slave 1, k = n the cable to the RED side; in a tree, the cable
    // entering slave k+1's port A.
    Expected<void, FaultError> break_link_after(std::size_t k);
    Expected<void, FaultError> repair_link_after(std::size_t k);
    // The carrier of the master side (ecsim follows the real interface).
    void set_side_link(Side side, bool up);
    // Splices a slave that is in no ENI (unknown_slave_description()) into
    // the segment so that it becomes slave `position` (1..n+1); remove takes
    // such a slave out again. Both re-plug cables: the neighbours see a link
    // loss and a new link, as with a real cable.
    Expected<void, FaultError> insert_unknown_slave(std::size_t position);
    Expected<void, FaultError> remove_unknown_slave(std::size_t position);
    // EEPROM alias (SII word 4; the ESC takes it over at its next EEPROM load)
    // and the explicit device ID selector.
    Expected<void, FaultError> set_eeprom_alias(std::size_t position, std::uint16_t alias);
    Expected<void, FaultError> set_id_selector(std::size_t position, std::uint16_t value);
    // The slave stack sends a CoE emergency; its FoE server asks for a
    // password (0: none) or answers the next `packets` DATA of a write BUSY.
    Expected<void, FaultError> send_emergency(std::size_t position, const wire::CoeEmergency& emergency);
    Expected<void, FaultError> set_foe_password(std::size_t position, std::uint32_t password);
    Expected<void, FaultError> set_foe_busy(std::size_t position, std::uint32_t packets);

    // ---- Hot-Connect (segment_hot_connect.cpp; groups 1..n as the ENI numbers them)
    // Power of every slave of a group.
    Expected<void, FaultError> set_group_power(std::size_t group, bool on);
    // Plugs the group's head into port `port` (0..3) of slave `position`
    // (unplugging it from where it was), or takes it out.
    Expected<void, FaultError> plug_group(std::size_t group, std::size_t position, int port);
    Expected<void, FaultError> unplug_group(std::size_t group);
    // A slave in no ENI, or a copy of slave `source` (same identity and
    // identification), plugged into a free port; it becomes the last slave.
    // remove_unknown_slave() takes either out again.
    Expected<void, FaultError> plug_unknown_slave(std::size_t position, int port);
    Expected<void, FaultError> plug_duplicate(std::size_t source, std::size_t position, int port);
    // The slave's application refuses `state` and above (nullopt: nothing).
    Expected<void, FaultError> refuse_states_from(std::size_t position, std::optional<eni::SlaveState> state);
    // The ETG.1020 legacy ID selector, read at the slave's next power-on.
    Expected<void, FaultError> set_legacy_id_selector(std::size_t position, std::uint16_t value);
    // The next `frames` frames arriving at port `port` (0..3) of slave
    // `position` are damaged there: that port counts invalid frames and RX
    // errors, every port after it on the frame's way forwarded RX errors, and
    // the master never gets them back (`ecsim ctl port-errors`).
    Expected<void, FaultError> inject_rx_errors(std::size_t position, int port, std::uint32_t frames);
    std::size_t group_count() const { return group_count_; }
    std::size_t group_of(std::size_t position) const { return origins_[position - 1].group; }

    // ---- inspection (positions 1..slave_count())
    std::size_t slave_count() const { return escs_.size(); }
    const Esc& slave(std::size_t position) const { return escs_[position - 1]; }
    bool is_unknown(std::size_t position) const { return origins_[position - 1].added; }
    bool side_link(Side side) const { return side_link_[static_cast<std::size_t>(side)]; }
    // Whether the PHY at the far end of a side's cable is there: the cable is
    // intact and the slave port it leads to belongs to a powered slave (a
    // side cabled straight to the other side: the cable alone). A real
    // master's interface has carrier only then; ecsim shows it by taking its
    // own end of that cable down (segment_runner.hpp).
    bool side_peer_alive(Side side) const;
    // Whether the cable after slave k exists and is intact.
    bool link_after_intact(std::size_t k) const;
    const Topology& topology() const { return topology_; }
    const SegmentCounters& counters() const { return counters_; }

private:
    Segment(std::vector<Esc> escs, Topology topology, SegmentOptions options);
    static Expected<Segment, TopologyError> build(std::vector<SlaveSpec> specs, SegmentOptions options,
                                                  const std::string& file);

    Expected<std::size_t, FaultError> slave_index(std::size_t position) const;
    Expected<std::size_t, FaultError> cable_after(std::size_t k) const;
    bool endpoint_alive(const Endpoint& end) const;
    bool cable_has_link(std::size_t cable) const;
    // Brings every ESC port's physical link in line with cables, power and
    // sides; each change is logged (at info when `announce`, else debug).
    void update_links(bool announce = true);
    // Takes the link away from the slave ports on these cables first (a
    // re-plugged cable), then update_links().
    void replug(std::span<const std::size_t> cables);
    // Delays and oscillator of a new ESC, from the options (its serial picks its drift).
    void fit_hardware(Esc& esc);
    void power_on_esc(std::size_t index);
    void note_time(std::uint64_t now_ns) {
        if (now_ns > now_ns_) now_ns_ = now_ns;
    }
    // After every call into an ESC (the frame reached it at `time_ns`): its DC steps (segment_dc.cpp).
    void watch_dc(std::size_t slave, std::uint64_t time_ns);

    // Where a slave came from: the ENI (with its group), or an operator's fault.
    struct Origin {
        bool added = false;      // insert-unknown, plug-unknown or plug-duplicate
        std::size_t group = 0;   // Hot-Connect group (0: mandatory, or added)
        bool group_head = false;
    };
    Expected<std::size_t, FaultError> group_head(std::size_t group) const;
    Expected<void, FaultError> plug_added(Esc esc, std::size_t position, int port, std::string_view what);

    // ---- carrying frames (segment_carry.cpp)
    // The step machine with the ESCs themselves, from `state` on; `frame`
    // is null for a frame that is not an EtherCAT datagram frame.
    detail::WalkResult walk_through_escs(detail::WalkState& state, wire::FrameView* frame, bool ethercat,
                                         std::uint64_t seq, detail::FrameHealth& health);
    // The fast pass: along the recorded route, calling only the ESCs the
    // frame may address or that are not passable. nullopt: not possible for
    // this frame (carry() takes the step machine).
    std::optional<detail::WalkResult> walk_fast(Side entry, wire::FrameView& frame, std::uint64_t now_ns,
                                                std::uint64_t seq);
    static detail::WalkState resume_after(const detail::RouteStep& step, std::size_t slave, std::uint64_t time_ns);
    void apply_passed_before(const detail::FrameRoute& route, std::uint32_t index, wire::FrameView& frame,
                             std::uint64_t seq);
    std::optional<Side> finish(const detail::WalkResult& result, Side entry, std::uint64_t seq,
                               detail::FrameHealth health = detail::FrameHealth::Intact);
    // Pass digests: taken again after every call into an ESC that may change
    // it; one that changes ports or power forgets the recorded routes.
    void refresh_digest(std::size_t slave);
    void refresh_digests();

    std::vector<Esc> escs_;
    std::vector<Origin> origins_;  // per slave
    std::size_t group_count_ = 0;
    Topology topology_;
    SegmentOptions options_;
    std::array<bool, kSideCount> side_link_{true, true};
    SegmentCounters counters_;
    std::uint64_t next_frame_seq_ = 1;
    std::uint64_t now_ns_ = 0;
    std::uint64_t next_oscillator_ = 0;  // serial of the next ESC's oscillator
    std::uint64_t rx_errors_pending_ = 0;  // the ESCs' pending port errors, summed: no fast pass while any
    std::unique_ptr<detail::FastPass> fast_;
    std::unique_ptr<detail::DcWatch> dc_;
};

}  // namespace ecpair::sim
