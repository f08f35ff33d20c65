#pragma once
// One emulated EtherCAT Slave Controller (ESC): the register file, the SII
// EEPROM behind its interface at 0x0500, the AL state machine, FMMUs and
// SyncManagers over process RAM, DC time registers, DL control/status with
// the per-port loop logic, and a small application on the PDI side.
//
// The segment (topology) owns a chain of Esc objects and moves frames
// between them; the Esc decides what its processing unit does to a frame
// and whether each of its ports is open. Both follow esc-facts.md.

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sim/mailbox.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::sim {

class FoeServer;
class EoeServer;
class SoeServer;

inline constexpr int kMaxPorts = 4;

// A SyncManager record (0x0800 + 8n) that the ENI's InitCmds write. The
// configurator took it from the device's ESI, and a real slave checks its
// SyncManagers against that same ESI (its SII), so the emulated SII follows it.
struct SmInitWrite {
    std::uint8_t index = 0;  // SM n
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    bool enable = false;
    bool bootstrap = false;  // written for INIT -> BOOT only (the bootstrap mailbox)
};

// Distributed clocks support (datasheet I §9.1: slaves with two ports need
// none; the others have at least the receive times, every ET1100 the whole
// 64-bit system time).
enum class DcSupport : std::uint8_t { None, Dc32, Dc64 };
std::string_view to_string(DcSupport support);  // "none", "32-bit", "64-bit"

// What is needed to build one ESC: identity, ports, the mailbox and process
// data layout (for the SII image, the checks of the AL state machine and the
// memory size).
struct EscDescription {
    std::string name;
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code = 0;
    std::uint32_t revision_no = 0;
    std::uint32_t serial_no = 0;
    std::uint16_t alias = 0;        // SII word 4, loaded into 0x0012 at power-on
    std::uint16_t id_selector = 0;  // the explicit device ID (e.g. a rotary switch)
    // ETG.1020 legacy: a rotary switch read at power-on and copied into 0x0012
    // (racing the SII alias, hot-connect.md §10); 0: the slave has none.
    std::uint16_t legacy_id_selector = 0;
    // Input-word identification: the application shows `value` at ESC address
    // `address` of its input process data (from SAFEOP on).
    struct InputWord {
        std::uint16_t address = 0;
        std::uint16_t value = 0;
    };
    std::optional<InputWord> input_word_id;
    std::string physics = "YY";     // one letter per implemented port (Y = MII, K = EBUS)
    std::optional<eni::Mailbox> mailbox;
    eni::ProcessData process_data;
    std::vector<SmInitWrite> sm_init_writes;  // in InitCmd order; records that only clear are left out
    DcSupport dc = DcSupport::Dc64;

    // From an ENI slave: identity, physics, mailbox, process data and the
    // SyncManager records its InitCmds write. The ENI's <Identification
    // Value> becomes the alias when its Ado is 0x0012, the explicit device ID
    // (id_selector) when it is 0x0134, and an input word when the Ado lies in
    // the process RAM (0x1000 and up). DC: 64-bit (the ENI cannot say 32);
    // Segment::from_eni takes it away from slaves the ENI shows to have none.
    static EscDescription from_eni(const eni::Slave& slave);
};

enum class LoopSetting : std::uint8_t { Auto = 0, AutoClose = 1, Open = 2, Closed = 3 };

// Passed with every frame the segment hands to the processing unit.
struct FrameContext {
    std::uint64_t time_ns = 0;    // simulated local time when the frame reaches the EPU
    std::uint64_t frame_seq = 0;  // unique per frame travelling the segment (DC receive-time latch)
};

enum class EpuVerdict : std::uint8_t { Forward, Destroy };

// ---- distributed clocks as ecsim sees them (the truth a master cannot read)

// An ESC's quartz: how far it runs off the common time base, and where its
// local time starts at a power-on: at 0 for start_seed 0, else at a value
// below 2^32 ns taken from the seed and the number of the power-on (a
// slave powered up some seconds before the master looks).
struct Oscillator {
    std::int64_t drift_ppb = 0;
    std::uint64_t start_seed = 0;
};

// How long a frame takes through an ESC, by the port it leaves by (the
// datasheet's t_F alongside the processing unit, t_P through it), from its
// arrival at a port (or at the processing unit) to its departure.
struct EscDelays {
    std::array<std::uint32_t, kMaxPorts> forwarding_ns{};
    std::array<std::uint32_t, kMaxPorts> processing_ns{};
    static EscDelays uniform(std::uint32_t forwarding, std::uint32_t processing) {
        EscDelays d;
        d.forwarding_ns.fill(forwarding);
        d.processing_ns.fill(processing);
        return d;
    }
    std::uint32_t leaving(int port, bool through_epu) const {
        return through_epu ? processing_ns[static_cast<std::size_t>(port)] : forwarding_ns[static_cast<std::size_t>(port)];
    }
    friend bool operator==(const EscDelays&, const EscDelays&) = default;
};

// What the segment looks at after every call of an ESC.
struct DcCounters {
    std::uint64_t steps = 0;            // clock steps (DcClockStep) so far
    std::uint64_t reference_reads = 0;  // ARMW/FRMW reads of its 0x0910 so far (it is the master's reference clock)
    bool sync0_running = false;         // cyclic unit and SYNC0 activated
    friend bool operator==(const DcCounters&, const DcCounters&) = default;
};

// A change of an ESC's system time against the common time base: a new rate
// (a received time fed the loop), a jump (a new offset), SYNC0 started or
// stopped. System times are unwrapped (a 32-bit DC's registers show the low half).
struct DcClockStep {
    std::uint64_t at_ns = 0;   // common time
    std::uint64_t before = 0;  // system time just before
    std::uint64_t after = 0;   // and just after
    bool sync0_before = false; // SYNC0 ran just before
    bool sync0_after = false;  // and just after
};

// One SYNC pulse: its nominal system time and when it came on the common time base.
struct SyncEdge {
    std::uint64_t system_ns = 0;
    std::uint64_t at_ns = 0;
};

struct DcTruth {
    DcSupport support = DcSupport::None;
    std::uint64_t system_time_ns = 0;  // the local copy of the system time at the time asked, unwrapped
    std::uint64_t local_time_ns = 0;
    std::int64_t drift_ppb = 0;        // the oscillator against the common time base
    bool sync0_running = false;        // cyclic unit and SYNC0 activated
    std::uint32_t sync0_cycle_ns = 0;
    std::optional<SyncEdge> last_sync0;
    std::optional<SyncEdge> previous_sync0;
    std::uint64_t sync0_missed = 0;    // cycles without a pulse while SYNC0 ran (since reset_dc_counters)
    std::uint64_t sync0_doubled = 0;   // pulses less than half a cycle after the one before
};

// What the segment needs of an ESC to carry a frame past it without calling
// it, when no datagram of the frame addresses it (the segment's fast pass).
// While `passable`, such a frame changes nothing in the ESC (the slave
// application runs only for frames that address it) and the ESC changes only
// three things in the frame: ADP of APxx datagrams (+1), every datagram's IRQ
// field (ORed with `irq`) and, with the forwarding rule, the source MAC's
// locally administered bit. The fields are a snapshot: the segment takes a
// new one after every call that may change the ESC.
struct PassDigest {
    // Nothing happens per frame: powered, port 0 open or set Open/Closed (no
    // circulating-frame check), no port in auto-close's closed wait, no
    // temporary loop setting running out.
    bool passable = false;
    bool powered = false;
    bool forwarding_rule = false;
    // An FMMU maps a register (below 0x1000): a logical write may reach DL
    // control or the DC latch, which read where the frame arrived.
    bool fmmu_maps_registers = false;
    std::uint8_t open_ports = 0;  // bit p: port_open(p)
    std::uint8_t logical_count = 0;
    std::uint16_t irq = 0;        // ECAT event request AND mask
    // What FPxx and Lxx match: the station address and alias (the alias
    // counts even when not enabled: a digest may say "addressed" too often,
    // never too rarely) and the logical bytes [begin, end) the active FMMUs
    // map, one range each; the last range covers all FMMUs from it on.
    std::uint16_t station_address = 0;
    std::uint16_t station_alias = 0;
    // The process data watchdog expires then: frames from that time on go through the ESC.
    std::uint64_t deadline_ns = std::numeric_limits<std::uint64_t>::max();
    struct LogicalRange {
        std::uint64_t begin = 0;
        std::uint64_t end = 0;
        friend bool operator==(const LogicalRange&, const LogicalRange&) = default;
    };
    static constexpr std::size_t kLogicalRanges = 2;  // the outputs and the inputs of most slaves
    std::array<LogicalRange, kLogicalRanges> logical{};
    EscDelays delays;  // how long a frame takes through it
    friend bool operator==(const PassDigest&, const PassDigest&) = default;
};

class Esc {
public:
    explicit Esc(EscDescription description);
    ~Esc();
    Esc(Esc&&) noexcept;
    Esc& operator=(Esc&&) noexcept;

    const EscDescription& description() const;

    // ---- processing unit (the port 0 -> EPU leg only)
    // Processes every datagram of a validated EtherCAT frame in place: ADP
    // increment, register/RAM/FMMU access, WKC, IRQ, the slave-forwarding bit
    // of the source MAC, the circulating bit when port 0 is closed. Register
    // writes, loop settings, EEPROM and AL commands take effect at the end of
    // the frame. Destroy: the frame dies here (second pass of a circulating frame).
    EpuVerdict process(wire::FrameView& frame, const FrameContext& context);
    // A non-EtherCAT frame reaching the EPU: destroyed when the forwarding rule
    // (0x0100 b0) is on, forwarded unchanged otherwise.
    EpuVerdict process_non_ethercat() const;
    // The ESC as a frame that does not address it sees it (see PassDigest).
    PassDigest pass_digest() const;

    // ---- time (the process data watchdog)
    // The ESC's clock reached `now_ns` without a frame (frames carry their own
    // time): an expired SM watchdog takes effect. The segment calls it when
    // next_deadline() passes.
    void advance_time(std::uint64_t now_ns);
    // When the ESC next needs advance_time() (nullopt: not before a frame).
    std::optional<std::uint64_t> next_deadline() const;

    // ---- ports
    int port_count() const;                 // implemented ports (from physics)
    bool port_implemented(int port) const;
    // Whether frames leave through / come back in through this port, from the
    // loop setting (0x0101), the physical link and the auto-close state.
    bool port_open(int port) const;
    LoopSetting loop_setting(int port) const;
    void set_physical_link(int port, bool up);  // the segment reports cable/peer changes
    bool physical_link(int port) const;
    // A frame reached this port from outside (valid CRC): latches DC receive
    // times when a latch is pending for this frame, and leaves auto-close's
    // "closed wait" when the port is in it.
    void frame_arrived_at_port(int port, std::uint64_t time_ns, std::uint64_t frame_seq);

    // ---- distributed clocks (DcUnit): the oscillator and the truth
    // The ESC's oscillator and where its local time starts at each power-on
    // (now, as if it had just been powered on). By default it is exact and
    // the local time starts at 0.
    void set_oscillator(const Oscillator& oscillator);
    // The local copy of the system time at common time `t`, unwrapped.
    std::uint64_t dc_system_time_at(std::uint64_t t) const;
    // The truth at common time `now_ns` (SYNC pulses taken up to it).
    DcTruth dc_truth(std::uint64_t now_ns);
    // What the segment watches after every call (cheap).
    DcCounters dc_counters() const;
    const DcClockStep& dc_last_step() const;
    void reset_dc_counters();

    // ---- propagation (set by the segment, which adds them up along a frame's way)
    void set_propagation_delays(const EscDelays& delays);
    const EscDelays& propagation_delays() const;

    // ---- receive errors (the error counters 0x0300-0x030B)
    // The PHY of `port` receives the next `frames` frames with an error (added
    // to those still pending; kept over a power cycle: the fault is the
    // cable's): `ecsim ctl port-errors`.
    void inject_rx_errors(int port, std::uint32_t frames);
    std::uint32_t rx_errors_pending(int port) const;
    // A frame reaches `port`: true when its PHY damages it (one pending error used up).
    bool take_rx_error(int port);
    // A damaged frame reached `port`: counted as an invalid frame and an RX
    // error, or as a forwarded RX error when an ESC upstream marked it
    // already. Nothing else happens (it opens no port in closed wait and
    // latches no receive time): the frame is not valid.
    void damaged_frame_arrived_at_port(int port, bool marked_upstream);

    // ---- power and faults
    bool powered() const;
    void power_off();
    // Registers to reset values, SII reloaded (alias -> 0x0012); the DC
    // local time starts again (Oscillator) at common time `now_ns`.
    void power_on(std::uint64_t now_ns = 0);
    // Rewrites SII word 4 and the CRC; 0x0012 follows at the next power-on
    // (an ESC takes the alias over only at the first SII load).
    void set_eeprom_alias(std::uint16_t alias);
    void set_id_selector(std::uint16_t value);  // read at the next ID request
    // ETG.1020 legacy rotary switch, read at the next power-on (0: none).
    void set_legacy_id_selector(std::uint16_t value);
    // The application refuses to enter `state` and every state above it
    // (PREOP/SAFEOP/OP; nullopt: refuses nothing): the lock-out use case.
    void refuse_states_from(std::optional<eni::SlaveState> state);

    // ---- PDI-side mailbox (the seam for protocol servers such as CoE)
    // Installs the application that answers mailbox requests. Without one the
    // ESC answers like a slave stack that supports no mailbox protocol: with a
    // mailbox error reply (see docs/ESC_EMULATION.md).
    void set_mailbox_handler(std::unique_ptr<MailboxHandler> handler);
    // Posts an unsolicited reply into SM1 (e.g. an emergency); false when SM1
    // is full or the mailbox is not running.
    bool post_mailbox_reply(ConstBytes reply);
    // The slave stack sends a CoE emergency (queued behind replies the
    // master has not read); why not when its mailbox offers no CoE, does not
    // run, or its queue is full.
    Expected<void, std::string> send_emergency(const wire::CoeEmergency& emergency);
    // The protocol servers of the slave stack (nullptr when it has none): the
    // FoE server's password, busy packets and files; what EoE and SoE hold.
    FoeServer* foe_server();
    const EoeServer* eoe_server() const;
    const SoeServer* soe_server() const;

    // ---- PDI-side view, for tests, the application and diagnostics
    // Raw memory access without ECAT semantics (no shadow, no SyncManager, no
    // event); the range is cut at 0xFFFF. FMMU and SyncManager configuration
    // written this way is taken over at once.
    std::vector<std::uint8_t> read_memory(std::uint16_t address, std::size_t length) const;
    void write_memory(std::uint16_t address, ConstBytes data);
    std::uint16_t station_address() const;
    std::uint16_t station_alias() const;
    std::uint8_t al_status() const;        // 0x0130 low byte (state + error bit)
    std::uint16_t al_status_code() const;  // 0x0134
    const std::vector<std::uint8_t>& sii_image() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace ecpair::sim
