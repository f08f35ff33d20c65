// The ESC facade: one frame through the processing unit, then the end of the
// frame, then the PDI side.
//
//  process():  powered off -> the frame dies. Port 0 closed under Auto or
//              Auto-close -> circulating-frame rule (C=1 on the first
//              datagram: destroy and count 0x030C; else set C on every
//              datagram). The DC unit notes the frame's time, every datagram
//              goes through the DatagramProcessor, and with the forwarding
//              rule on the source MAC gets its locally administered bit.
//  end of frame: staged register writes are committed and their owners react
//              (DL control -> ports, error counters, SII commands, FMMU and
//              SyncManager configuration, DC latches, loop, offset, cyclic unit).
//  PDI side:   when the SII configuration is loaded, the slave stack runs the
//              AL state machine (SyncManager changes first, then AL control),
//              enables/deactivates SyncManagers for the new state, serves the
//              mailbox and runs the application. In device emulation (0x0141
//              b0, from the SII) there is no stack: AL status follows AL
//              control. Finally DL status is recomputed (raising its ECAT
//              event when it changed).
//  time:       a frame's time (and advance_time()) expires the process data
//              watchdog: outputs cleared; a stack in OP falls to SAFEOP+ERR
//              0x001B. The DC clocks need no time of their own: they are
//              computed at the common time asked (dc_registers.hpp).

#include "ecpair/sim/esc.hpp"

#include <algorithm>
#include <optional>

#include <fmt/format.h>

#include "al_state_machine.hpp"
#include "datagram_processor.hpp"
#include "dc_registers.hpp"
#include "dl_registers.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sim/coe_server.hpp"
#include "ecpair/sim/eoe_server.hpp"
#include "ecpair/sim/foe_server.hpp"
#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/sim/soe_server.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "error_counters.hpp"
#include "esc_coe_context.hpp"
#include "esc_layout.hpp"
#include "esc_memory.hpp"
#include "fmmu.hpp"
#include "legacy_id_selector.hpp"
#include "mailbox_service.hpp"
#include "physical_access.hpp"
#include "port_logic.hpp"
#include "process_data_watchdog.hpp"
#include "register_map.hpp"
#include "sii_eeprom.hpp"
#include "sii_image.hpp"
#include "slave_application.hpp"
#include "slave_stack_checks.hpp"
#include "sync_manager.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint64_t kTemporaryLoopNs = 1'000'000'000;  // "about one second"
constexpr std::uint8_t kTemporaryLoop = 0x02;

bool valid_port(int port) { return port >= 0 && port < kMaxPorts; }

std::size_t largest_slave_mailbox(const EscLayout& layout) {
    std::size_t largest = 0;
    for (const auto& areas : {layout.mailbox, layout.bootstrap}) {
        if (areas) largest = std::max<std::size_t>(largest, areas->in.length);
    }
    return largest;
}

}  // namespace

struct Esc::Impl {
    explicit Impl(EscDescription d)
        : description(std::move(d)),
          layout(EscLayout::of(description)),
          log(logger("esc")),
          owner(fmt::format("slave {:?}", description.name)),
          sync_managers(memory),
          physical(memory, sync_managers),
          datagrams(memory, physical, fmmus),
          eeprom(build_sii_image(description, layout)),
          ports(layout.port_count, log, owner),
          dc(memory, description.dc),
          watchdog(memory),
          al(memory, log, owner),
          checks(layout, sync_managers, memory),
          mailbox(memory, sync_managers, largest_slave_mailbox(layout)),
          application(memory, sync_managers, layout),
          coe_context(memory, al, layout, log, owner),
          legacy(log, owner) {
        physical.set_computed_registers(&dc);
        checks.set_id_selector(description.id_selector);
        checks.set_legacy(&legacy);
        legacy.set(description.legacy_id_selector);
        if (description.input_word_id) {
            application.show_word(description.input_word_id->address, description.input_word_id->value);
        }
        install_mailbox_server();
        power_on(0);
    }

    // The layout points into `description`, so neither may move: Impl lives
    // behind a unique_ptr and is never copied.
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;

    // A slave whose mailbox offers CoE, FoE, EoE or SoE (or has their
    // InitCmds) answers them (docs/ESC_EMULATION.md "Mailbox"); the
    // others answer every request with a mailbox error.
    void install_mailbox_server();
    EpuVerdict process(wire::FrameView& frame, const FrameContext& context);
    void end_of_frame(const FrameContext& context, bool addressed);
    // `addressed`: a datagram of the frame addressed this ESC; the
    // application runs only then (a frame passing by changes nothing here).
    void run_slave_stack(bool al_control_written, bool sm_activation_changed, bool addressed);
    void on_dl_control_written(const FrameContext& context, std::uint8_t loop_before);
    void expire_temporary_loop(std::uint64_t now_ns);
    void apply_state(AlState state);
    void advance_time(std::uint64_t now_ns);
    void on_watchdog_expired();
    void update_dl_status();
    void power_on(std::uint64_t now_ns);
    std::optional<int> entry_port(std::uint64_t frame_seq) const;
    // Asked for every frame at every slave: the bit alone, not the whole register decoded (DlControl::decode).
    bool forwarding_rule() const { return (memory.u8(reg::kDlControl) & 0x01U) != 0; }
    bool device_emulation() const { return (memory.u8(regs::kEscConfig) & 0x01) != 0; }

    const EscDescription description;
    EscLayout layout;  // not const: a CoE PDO assignment changes the expected process data sizes
    std::shared_ptr<spdlog::logger> log;
    std::string owner;
    EscMemory memory;
    SyncManagerUnit sync_managers;
    FmmuUnit fmmus;
    PhysicalAccess physical;
    DatagramProcessor datagrams;
    SiiEeprom eeprom;
    PortLogic ports;
    DcUnit dc;
    ProcessDataWatchdog watchdog;
    AlStateMachine al;
    SlaveStackChecks checks;
    MailboxService mailbox;
    SlaveApplication application;
    EscCoeContext coe_context;
    LegacyIdSelector legacy;
    MailboxServer* mailbox_server = nullptr;  // owned by `mailbox` while installed

    // What DL status (0x0110) was last computed from; nullopt: not since power-on.
    struct DlStatusInputs {
        std::uint32_t ports_version = 0;
        bool pdi_operational = false;
        friend bool operator==(const DlStatusInputs&, const DlStatusInputs&) = default;
    };
    std::optional<DlStatusInputs> dl_status_from;

    bool powered = false;
    std::array<std::optional<std::uint64_t>, kMaxPorts> arrival_seq{};
    std::array<std::uint32_t, kMaxPorts> rx_errors_pending{};  // frames each port's PHY will damage
    std::optional<std::uint64_t> temporary_loop_until_ns;
    std::uint8_t permanent_loop_byte = 0;
    EscDelays delays;  // the segment's to use
};

EpuVerdict Esc::Impl::process(wire::FrameView& frame, const FrameContext& context) {
    if (!powered) return EpuVerdict::Destroy;
    advance_time(context.time_ns);
    expire_temporary_loop(context.time_ns);
    if (ports.circulating_frame_check()) {
        if ((*frame.begin()).circulating()) {
            error_counters::count_processing_unit_error(memory);
            log->debug("{}: circulating frame {} destroyed", owner, context.frame_seq);
            return EpuVerdict::Destroy;
        }
        for (auto datagram : frame) datagram.set_circulating(true);
    }
    dc.start_of_frame(context.time_ns);
    bool addressed = false;
    for (auto datagram : frame) addressed = datagrams.process(datagram) || addressed;
    if (forwarding_rule()) {
        wire::MacAddress source = frame.ethernet().source;
        source.bytes[0] = static_cast<std::uint8_t>(source.bytes[0] | 0x02);
        frame.set_source(source);
    }
    end_of_frame(context, addressed);
    return EpuVerdict::Forward;
}

void Esc::Impl::end_of_frame(const FrameContext& context, bool addressed) {
    bool al_control_written = false;
    std::uint8_t activation_changed = 0;
    const DcFrameAccess dc_access = datagrams.take_dc_access();
    if (memory.has_staged()) {
        eeprom.filter_staged(memory);
        dc.filter_staged();
        const std::uint8_t loop_before = memory.u8(reg::kDlControlLoop);
        memory.commit_staged();
        if (memory.staged_any(reg::kDlControl, reg::kDlControl + 4)) on_dl_control_written(context, loop_before);
        al_control_written = memory.staged_any(reg::kAlControl, reg::kAlControl + 2);
        error_counters::apply_clearing_writes(memory);
        if (memory.staged_any(reg::kSiiConfig, reg::kSiiData + 8)) {
            physical.set_process_ram_available(eeprom.on_ecat_write(memory));
        }
        if (memory.staged_any(reg::kFmmuBase, reg::kSmBase)) fmmus.refresh(memory);
        if (memory.staged_any(reg::kSmBase, reg::kDcReceiveTimes)) activation_changed = sync_managers.refresh();
        dc.end_of_frame(context.frame_seq, dc_access);
        if (memory.staged_any(regs::kWatchdogTimeProcessData, regs::kWatchdogTimeProcessData + 2)) watchdog.reset();
        memory.clear_staged();
    } else if (dc_access.reference_read) {
        dc.end_of_frame(context.frame_seq, dc_access);
    }
    if (sync_managers.take_watchdog_trigger()) watchdog.trigger(context.time_ns);
    run_slave_stack(al_control_written, activation_changed != 0, addressed);
    update_dl_status();
}

void Esc::Impl::run_slave_stack(bool al_control_written, bool sm_activation_changed, bool addressed) {
    if (!eeprom.loaded()) return;  // the PDI is not operational
    if (device_emulation()) {
        if (al_control_written) al.on_control_written_device_emulation();
        if (addressed) application.after_frame(al.state());
        return;
    }
    bool state_changed = false;
    if (sm_activation_changed) state_changed = al.on_sm_activation_changed(checks) || state_changed;
    if (al_control_written) {
        const AlState before = al.state();
        state_changed = al.on_control_written(checks) || state_changed;
        legacy.after_request(AlControlWord::decode(memory.load<std::uint16_t>(reg::kAlControl)), before, al.state(),
                             memory.load<std::uint16_t>(reg::kAlStatusCode), eeprom);
    }
    if (state_changed) apply_state(al.state());
    mailbox.after_frame();
    if (addressed) application.after_frame(al.state());
}

void Esc::Impl::install_mailbox_server() {
    if (!layout.has_mailbox()) return;
    const auto offered = layout.mailbox_protocols;
    std::vector<std::unique_ptr<MailboxProtocol>> protocols;
    if ((offered & eni::kCoE) != 0) {
        protocols.push_back(std::make_unique<CoeServer>(ObjectDictionary::for_slave(description), coe_context,
                                                        layout.mailbox->in.length));
    }
    if ((offered & eni::kFoE) != 0) {
        protocols.push_back(std::make_unique<FoeServer>(layout.mailbox->out.length, layout.mailbox->in.length));
    }
    if ((offered & eni::kEoE) != 0) protocols.push_back(std::make_unique<EoeServer>());
    if ((offered & eni::kSoE) != 0) {
        protocols.push_back(std::make_unique<SoeServer>(
            description.mailbox ? description.mailbox->soe_init_cmds : std::vector<eni::SoeInitCmd>{}));
    }
    if (protocols.empty()) return;
    auto server = std::make_unique<MailboxServer>(coe_context, layout.mailbox->in.length, std::move(protocols));
    mailbox_server = server.get();
    mailbox.set_handler(std::move(server));
}

// What the slave stack does with its SyncManagers in each state, as SOES:
// mailbox SMs run from PREOP (and in BOOT), process data SMs in SAFEOP/OP;
// the others are deactivated from the PDI side. Without a stack (device
// emulation) nothing deactivates them.
void Esc::Impl::apply_state(AlState state) {
    if (device_emulation()) {
        for (int n = 0; n < EscLayout::kSmCount; ++n) sync_managers.set_pdi_deactivated(n, false);
        return;
    }
    const bool mailbox_on = state != AlState::Init;
    const bool process_data_on = state == AlState::Safeop || state == AlState::Op;
    for (int n = 0; n < EscLayout::kSmCount; ++n) {
        switch (layout.sms[static_cast<std::size_t>(n)].role) {
            case SmRole::MailboxOut:
            case SmRole::MailboxIn: sync_managers.set_pdi_deactivated(n, !mailbox_on); break;
            case SmRole::Outputs:
            case SmRole::Inputs: sync_managers.set_pdi_deactivated(n, !process_data_on); break;
            case SmRole::Unused: break;
        }
    }
    mailbox.set_running(mailbox_on && layout.has_mailbox());
}

void Esc::Impl::advance_time(std::uint64_t now_ns) {
    if (watchdog.advance(now_ns)) on_watchdog_expired();
}

// The ESC clears the outputs (the digital output pins; the output buffers,
// as a stack puts its outputs into their safe state); a stack in OP falls
// to SAFEOP with the error flag and 0x001B, as SOES and the Beckhoff stack
// do. Device emulation has no stack: the AL state stays.
void Esc::Impl::on_watchdog_expired() {
    for (int n = 0; n < EscLayout::kSmCount; ++n) {
        if (layout.sms[static_cast<std::size_t>(n)].role != SmRole::Outputs) continue;
        const SmChannel& channel = sync_managers.channel(n);
        const std::uint32_t end = std::min<std::uint32_t>(channel.end(), regs::kAddressSpace);
        for (std::uint32_t a = channel.start; a < end; ++a) memory.set_u8(static_cast<std::uint16_t>(a), 0);
    }
    log->warn("{}: SM watchdog expired (no process data written), outputs cleared", owner);
    if (device_emulation() || !eeprom.loaded()) return;
    if (al.on_local_error(AlState::Safeop, al_code::kSmWatchdog, "SM watchdog")) apply_state(al.state());
}

void Esc::Impl::on_dl_control_written(const FrameContext& context, std::uint8_t loop_before) {
    if (!memory.staged_any(reg::kDlControlLoop, reg::kDlControlLoop + 1)) return;
    const DlControl control = DlControl::decode(memory.load<std::uint32_t>(reg::kDlControl));
    if (control.temporary) {
        if (!temporary_loop_until_ns) permanent_loop_byte = loop_before;
        temporary_loop_until_ns = context.time_ns + kTemporaryLoopNs;
    } else {
        temporary_loop_until_ns.reset();
    }
    ports.set_loop_settings(control.loop, entry_port(context.frame_seq).value_or(0));
}

void Esc::Impl::expire_temporary_loop(std::uint64_t now_ns) {
    if (!temporary_loop_until_ns || now_ns < *temporary_loop_until_ns) return;
    temporary_loop_until_ns.reset();
    memory.set_u8(reg::kDlControlLoop, permanent_loop_byte);
    memory.set_u8(regs::kDlControlFlags, static_cast<std::uint8_t>(memory.u8(regs::kDlControlFlags) & ~kTemporaryLoop));
    log->info("{}: temporary loop settings expired", owner);
    ports.set_loop_settings(DlControl::decode_loop(permanent_loop_byte), std::nullopt);
    update_dl_status();
}

std::optional<int> Esc::Impl::entry_port(std::uint64_t frame_seq) const {
    for (int p = 0; p < kMaxPorts; ++p) {
        if (arrival_seq[static_cast<std::size_t>(p)] == frame_seq) return p;
    }
    return std::nullopt;
}

void Esc::Impl::update_dl_status() {
    // Asked for at every port a frame passes; the ports and the PDI change rarely.
    const DlStatusInputs inputs{ports.version(), eeprom.loaded()};
    if (dl_status_from == inputs) return;
    dl_status_from = inputs;
    const std::uint16_t status = dl_status(ports, eeprom.loaded());
    if (status == memory.load<std::uint16_t>(reg::kDlStatus)) return;
    memory.store<std::uint16_t>(reg::kDlStatus, status);
    const auto request = memory.load<std::uint16_t>(reg::kEcatEventRequest);
    memory.store<std::uint16_t>(reg::kEcatEventRequest, static_cast<std::uint16_t>(request | regs::kEventDlStatus));
}

void Esc::Impl::power_on(std::uint64_t now_ns) {
    powered = true;
    memory.clear();
    dl_status_from.reset();  // the register is back at its reset value
    regs::write_reset_values(memory.bytes(),
                             regs::EscHardware{static_cast<std::uint8_t>(layout.ram_bytes / 1024), layout.port_descriptor(),
                                               description.dc != DcSupport::None, description.dc == DcSupport::Dc64});
    memory.set_ram_bytes(layout.ram_bytes);
    sync_managers.reset();
    fmmus.reset();
    watchdog.reset();
    const bool loaded = eeprom.power_on(memory);
    dc.power_on(now_ns);
    if (loaded) legacy.on_power_on(memory, eeprom);
    physical.set_process_ram_available(loaded);
    ports.reset();
    al.reset();
    apply_state(AlState::Init);
    application.reset();
    arrival_seq = {};
    temporary_loop_until_ns.reset();
    update_dl_status();
    if (loaded) {
        log->info("{}: power on", owner);
    } else {
        log->warn("{}: power on, SII configuration checksum wrong: not loaded, PDI not operational", owner);
    }
}

// ------------------------------------------------------------------ Esc

Esc::Esc(EscDescription description) : impl_(std::make_unique<Impl>(std::move(description))) {}
Esc::~Esc() = default;
Esc::Esc(Esc&&) noexcept = default;
Esc& Esc::operator=(Esc&&) noexcept = default;

const EscDescription& Esc::description() const { return impl_->description; }

EpuVerdict Esc::process(wire::FrameView& frame, const FrameContext& context) { return impl_->process(frame, context); }

EpuVerdict Esc::process_non_ethercat() const {
    if (!impl_->powered) return EpuVerdict::Destroy;
    return impl_->forwarding_rule() ? EpuVerdict::Destroy : EpuVerdict::Forward;
}

PassDigest Esc::pass_digest() const {
    const Impl& esc = *impl_;
    PassDigest digest;
    digest.powered = esc.powered;
    digest.delays = esc.delays;
    if (!esc.powered) return digest;
    digest.passable = !esc.ports.circulating_frame_check() && !esc.ports.any_closed_wait() &&
                      !esc.temporary_loop_until_ns;
    digest.forwarding_rule = esc.forwarding_rule();
    for (int p = 0; p < kMaxPorts; ++p) {
        if (esc.ports.open(p)) digest.open_ports = static_cast<std::uint8_t>(digest.open_ports | (1U << p));
    }
    digest.irq = static_cast<std::uint16_t>(esc.memory.load<std::uint16_t>(reg::kEcatEventRequest) &
                                            esc.memory.load<std::uint16_t>(reg::kEcatEventMask));
    digest.station_address = esc.memory.load<std::uint16_t>(reg::kStationAddress);
    digest.station_alias = esc.memory.load<std::uint16_t>(reg::kStationAlias);
    const std::size_t fmmus = esc.fmmus.active_count();
    for (std::size_t f = 0; f < fmmus; ++f) {
        const FmmuUnit::LogicalBytes bytes = esc.fmmus.logical_bytes(f);
        const std::size_t slot = std::min(f, PassDigest::kLogicalRanges - 1);
        auto& range = digest.logical[slot];
        if (f <= slot) {
            range = {bytes.begin, bytes.end};
        } else {
            range = {std::min(range.begin, bytes.begin), std::max(range.end, bytes.end)};
        }
    }
    digest.logical_count = static_cast<std::uint8_t>(std::min(fmmus, PassDigest::kLogicalRanges));
    digest.fmmu_maps_registers = esc.fmmus.maps_physical_below(regs::kProcessRam);
    if (const auto deadline = esc.watchdog.deadline()) digest.deadline_ns = *deadline;
    return digest;
}

int Esc::port_count() const { return impl_->layout.port_count; }
bool Esc::port_implemented(int port) const { return impl_->ports.implemented(port); }
bool Esc::port_open(int port) const { return impl_->powered && impl_->ports.open(port); }

LoopSetting Esc::loop_setting(int port) const {
    return valid_port(port) ? impl_->ports.setting(port) : LoopSetting::Closed;
}

void Esc::set_physical_link(int port, bool up) {
    const bool lost = impl_->ports.set_link(port, up);
    if (!impl_->powered) return;
    if (lost) error_counters::count_lost_link(impl_->memory, port);
    impl_->update_dl_status();
}

bool Esc::physical_link(int port) const { return impl_->ports.implemented(port) && impl_->ports.link(port); }

void Esc::frame_arrived_at_port(int port, std::uint64_t time_ns, std::uint64_t frame_seq) {
    if (!impl_->powered || !valid_port(port)) return;
    impl_->arrival_seq[static_cast<std::size_t>(port)] = frame_seq;
    impl_->dc.port_arrival(port, time_ns, frame_seq);
    impl_->ports.frame_received(port);
    impl_->update_dl_status();
}

void Esc::inject_rx_errors(int port, std::uint32_t frames) {
    if (!valid_port(port)) return;
    auto& pending = impl_->rx_errors_pending[static_cast<std::size_t>(port)];
    pending = frames > std::numeric_limits<std::uint32_t>::max() - pending ? std::numeric_limits<std::uint32_t>::max()
                                                                          : pending + frames;
}

std::uint32_t Esc::rx_errors_pending(int port) const {
    return valid_port(port) ? impl_->rx_errors_pending[static_cast<std::size_t>(port)] : 0;
}

bool Esc::take_rx_error(int port) {
    if (!valid_port(port)) return false;
    auto& pending = impl_->rx_errors_pending[static_cast<std::size_t>(port)];
    if (pending == 0) return false;
    --pending;
    return true;
}

void Esc::damaged_frame_arrived_at_port(int port, bool marked_upstream) {
    if (!impl_->powered || !valid_port(port)) return;
    error_counters::count_received_error(impl_->memory, port, marked_upstream);
}

void Esc::advance_time(std::uint64_t now_ns) {
    if (impl_->powered) impl_->advance_time(now_ns);
}

std::optional<std::uint64_t> Esc::next_deadline() const {
    if (!impl_->powered) return std::nullopt;
    return impl_->watchdog.deadline();
}

bool Esc::powered() const { return impl_->powered; }

void Esc::power_off() {
    if (!impl_->powered) return;
    impl_->powered = false;
    impl_->mailbox.set_running(false);
    impl_->log->info("{}: power off", impl_->owner);
}

void Esc::power_on(std::uint64_t now_ns) { impl_->power_on(now_ns); }

void Esc::set_oscillator(const Oscillator& oscillator) { impl_->dc.set_oscillator(oscillator); }

std::uint64_t Esc::dc_system_time_at(std::uint64_t t) const { return impl_->dc.system_time_at(t); }

DcTruth Esc::dc_truth(std::uint64_t now_ns) {
    DcUnit& dc = impl_->dc;
    DcTruth truth;
    truth.support = dc.support();
    truth.drift_ppb = dc.drift_ppb();
    if (!impl_->powered || !dc.has_system_time()) return truth;
    dc.advance_sync(now_ns);
    truth.system_time_ns = dc.system_time_at(now_ns);
    truth.local_time_ns = dc.local_time_at(now_ns);
    const SyncUnit& sync = dc.sync();
    truth.sync0_running = sync.sync0_running();
    truth.sync0_cycle_ns = sync.cycle_ns();
    truth.last_sync0 = sync.last_pulse();
    truth.previous_sync0 = sync.previous_pulse();
    truth.sync0_missed = sync.missed();
    truth.sync0_doubled = sync.doubled();
    return truth;
}

DcCounters Esc::dc_counters() const { return impl_->dc.counters(); }
const DcClockStep& Esc::dc_last_step() const { return impl_->dc.last_step(); }
void Esc::reset_dc_counters() { impl_->dc.reset_sync_counters(); }

void Esc::set_propagation_delays(const EscDelays& delays) { impl_->delays = delays; }
const EscDelays& Esc::propagation_delays() const { return impl_->delays; }

void Esc::set_eeprom_alias(std::uint16_t alias) { impl_->eeprom.set_alias(alias); }

void Esc::set_id_selector(std::uint16_t value) { impl_->checks.set_id_selector(value); }

void Esc::set_legacy_id_selector(std::uint16_t value) { impl_->legacy.set(value); }

void Esc::refuse_states_from(std::optional<eni::SlaveState> state) {
    impl_->checks.refuse_from(state ? static_cast<std::uint8_t>(*state) : std::uint8_t{0});
    impl_->log->info("{}: {}", impl_->owner,
                     state ? fmt::format("refuses {} and above", eni::to_string(*state)) : std::string("refuses no state"));
}

void Esc::set_mailbox_handler(std::unique_ptr<MailboxHandler> handler) {
    impl_->mailbox_server = nullptr;
    impl_->mailbox.set_handler(std::move(handler));
}

bool Esc::post_mailbox_reply(ConstBytes reply) { return impl_->mailbox.post(reply); }

Expected<void, std::string> Esc::send_emergency(const wire::CoeEmergency& emergency) {
    if (impl_->mailbox_server == nullptr || impl_->mailbox_server->protocol(wire::MailboxType::CoE) == nullptr) {
        return unexpected(std::string("its mailbox offers no CoE"));
    }
    if (!impl_->mailbox.running()) return unexpected(std::string("its mailbox does not run (INIT or no power)"));
    if (!impl_->mailbox_server->send_unsolicited(wire::MailboxType::CoE, CoeServer::emergency(emergency),
                                                 impl_->mailbox)) {
        return unexpected(std::string("its mailbox queue is full (the master does not read SM1)"));
    }
    impl_->log->info("{}: CoE emergency 0x{:04x} sent", impl_->owner, emergency.error_code);
    return {};
}

FoeServer* Esc::foe_server() {
    return impl_->mailbox_server ? dynamic_cast<FoeServer*>(impl_->mailbox_server->protocol(wire::MailboxType::FoE))
                                 : nullptr;
}

const EoeServer* Esc::eoe_server() const {
    return impl_->mailbox_server ? dynamic_cast<const EoeServer*>(impl_->mailbox_server->protocol(wire::MailboxType::EoE))
                                 : nullptr;
}

const SoeServer* Esc::soe_server() const {
    return impl_->mailbox_server ? dynamic_cast<const SoeServer*>(impl_->mailbox_server->protocol(wire::MailboxType::SoE))
                                 : nullptr;
}

std::vector<std::uint8_t> Esc::read_memory(std::uint16_t address, std::size_t length) const {
    const auto bytes = impl_->memory.bytes();
    const std::size_t available = std::min<std::size_t>(length, bytes.size() - address);
    return {bytes.begin() + address, bytes.begin() + static_cast<std::ptrdiff_t>(address + available)};
}

void Esc::write_memory(std::uint16_t address, ConstBytes data) {
    Bytes bytes = impl_->memory.bytes();
    const std::size_t available = std::min<std::size_t>(data.size(), bytes.size() - address);
    std::copy_n(data.begin(), available, bytes.begin() + address);
    // Keep the decoded FMMU/SyncManager configuration in step with the registers.
    const std::size_t end = address + available;
    if (address < reg::kSmBase && end > reg::kFmmuBase) impl_->fmmus.refresh(impl_->memory);
    if (address < reg::kDcReceiveTimes && end > reg::kSmBase) impl_->sync_managers.refresh();
}

std::uint16_t Esc::station_address() const { return impl_->memory.load<std::uint16_t>(reg::kStationAddress); }
std::uint16_t Esc::station_alias() const { return impl_->memory.load<std::uint16_t>(reg::kStationAlias); }
std::uint8_t Esc::al_status() const { return impl_->memory.u8(reg::kAlStatus); }
std::uint16_t Esc::al_status_code() const { return impl_->memory.load<std::uint16_t>(reg::kAlStatusCode); }
const std::vector<std::uint8_t>& Esc::sii_image() const { return impl_->eeprom.image(); }

}  // namespace ecpair::sim
