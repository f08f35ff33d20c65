// Start-up order matters: links and the master exist before any thread runs;
// receive threads start before the cycle thread so that the first returned
// frames find a reader; the state machine is asked for the target state once
// the cycle runs (its requests travel through the cycle). Shutdown goes the
// other way round.

#include "daemon.hpp"

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/eni/loader.hpp"
#include "forwarding_path.hpp"

namespace ecpair::daemon {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("ecpaird"); }

}  // namespace

Daemon::Daemon(config::DaemonSettings settings) : settings_(std::move(settings)) {}

Daemon::~Daemon() { stop_threads(); }

std::chrono::microseconds Daemon::cycle_time() const {
    if (settings_.cycle_time_from_config) return settings_.cycle_time;
    for (const auto& cyclic : eni_->cyclic) {
        if (cyclic.cycle_time_us && *cyclic.cycle_time_us > 0) return std::chrono::microseconds(*cyclic.cycle_time_us);
    }
    return settings_.cycle_time;
}

int Daemon::open_links() {
    auto main = link::PcapLink::open(settings_.main_interface);
    if (!main) {
        log()->error("MAIN: {}", main.error().message);
        return kLinkFailure;
    }
    main_link_ = std::move(*main);
    if (!settings_.red_interface.empty()) {
        auto red = link::PcapLink::open(settings_.red_interface);
        if (!red) {
            log()->error("RED: {}", red.error().message);
            return kLinkFailure;
        }
        red_link_ = std::move(*red);
    }
    std::vector<std::string> watched{settings_.main_interface};
    if (red_link_) watched.push_back(settings_.red_interface);
    auto monitor = link::LinkStateMonitor::open(watched);
    if (!monitor) {
        log()->error("link monitor: {}", monitor.error().message);
        return kLinkFailure;
    }
    link_monitor_ = std::move(*monitor);
    return kOk;
}

int Daemon::open() {
    auto eni = eni::load_eni_file(settings_.eni_path);
    if (!eni) {
        log()->error("{}", eni.error().describe());
        return kBadConfig;
    }
    eni_ = *eni;

    if (const int rc = open_link_guard(); rc != kOk) return rc;  // first: it brings the links up
    if (const int rc = open_links(); rc != kOk) return rc;

    master::MasterOptions options;
    options.cycle_time = cycle_time();
    options.cable_redundancy = settings_.cable_redundancy;
    options.split_lrw = settings_.split_lrw;
    options.max_acyclic_frames_per_cycle = settings_.max_acyclic_frames_per_cycle;
    // Alone on its bus nothing needs a frame before the next cycle: the cycle reads the links itself.
    options.receive_in_cycle = !settings_.redundancy.enabled;
    auto created = master::Master::create(eni_, options, *main_link_, red_link_.get(), events_);
    if (!created) {
        log()->error("{}", created.error());
        return kBadConfig;
    }
    master_ = std::move(*created);
    describer_ = std::make_unique<master::EventDescriber>(eni_, &master_->plan());

    demo_ = std::make_unique<DemoApplication>(*eni_, settings_.demo, settings_.demo_step_cycles);
    master_->set_cycle_hook([this](master::ProcessImage& image, const master::CycleInfo& info) { on_cycle(image, info); });

    open_hot_connect();
    sequencer::StateMachineHooks hooks;
    hooks.request_cyclic_state = [this](eni::SlaveState s) { master_->request_state(s); };
    hooks.cyclic_state = [this] { return master_->state(); };
    hooks.on_done = [this](const sequencer::SequenceResult& result) { on_sequence_done(result); };
    hooks.on_start = [this] { hot_connect_->on_sequence_busy(); };
    hooks.on_scan = [this](const sequencer::ScanOutcome& outcome) { hot_connect_->on_startup_scan(outcome); };
    mailboxes_ = std::make_unique<sequencer::SlaveMailboxes>(*eni_, master_->bus(), sequencer::steady_clock());
    sequencer::StateMachineOptions state_machine_options;
    state_machine_options.mailboxes = mailboxes_.get();
    state_machine_ = std::make_unique<sequencer::MasterStateMachine>(eni_, master_->bus(), std::move(hooks), &events_,
                                                                     sequencer::steady_clock(), state_machine_options);
    sequencer::MailboxServiceHooks mailbox_hooks;
    mailbox_hooks.present = [this](std::size_t slave) { return master_->slaves().get(slave).present; };
    mailbox_hooks.events = &events_;
    mailbox_service_ = std::make_unique<sequencer::MailboxService>(eni_, master_->bus(), *mailboxes_, mailbox_hooks);
    hot_connect_->set_presence_listener([this](const std::vector<bool>& present, const std::vector<std::uint16_t>& shift) {
        state_machine_->update_presence(present, shift);
    });
    if (const int rc = open_redundancy(); rc != kOk) return rc;
    // Presence events come from Hot-Connect (after identification), not from every poll.
    slave_monitor_ = std::make_unique<sequencer::SlaveMonitor>(
        eni_, master_->bus(), master_->slaves(), &events_,
        [this] { return master_->state() != eni::SlaveState::Init; },  // station addresses are assigned from PREOP on
        std::chrono::milliseconds(100), /*report_presence=*/false);

    master::CycleThreadOptions cycle;
    cycle.period = master_->options().cycle_time;
    cycle.realtime_priority = settings_.realtime_priority;
    cycle_thread_ = std::make_unique<master::CycleThread>(cycle, [this](link::Clock::time_point deadline) {
        if (reception_) reception_->before_cycle();
        master_->run_cycle(deadline);
        if (reception_) reception_->after_cycle();
    });
    // A standby runs its cycle in step with the ACTIVE partner's.
    if (redundancy_) cycle_thread_->set_phase_reference([this] { return redundancy_->phase_reference(); });
    cycle_thread_->set_stall_listener([this](std::chrono::nanoseconds late, std::uint64_t skipped) {
        const auto late_us = std::chrono::duration_cast<std::chrono::microseconds>(late).count();
        events_.push(master::Event{master::events::kCycleStall, master_->cycle(), std::chrono::system_clock::now(),
                                   static_cast<std::uint32_t>(late_us), static_cast<std::uint32_t>(skipped), 0, 0});
    });

    operator_service_ = std::make_unique<OperatorService>(settings_, *master_, *state_machine_, *cycle_thread_, *demo_,
                                                          redundancy_.get(), supervisor_.get(), *hot_connect_service_);
    operator_service_->set_tap_bridge(tap_bridge_.get());
    operator_service_->set_link_guard(link_guard_.get());
    if (link_guard_) link_guard_policy_ = make_link_guard_policy();
    control_server_ = std::make_unique<control::ControlServer>(
        io_, *operator_service_, control::SocketSettings{settings_.control_path, settings_.control_mode, settings_.control_group,
                                                   settings_.control_request_timeout, settings_.control_max_clients});
    if (auto opened = control_server_->open(); !opened) {
        log()->error("{}", opened.error());
        return kBadConfig;
    }

    log()->info("{}: ENI {} ({} slaves), MAIN {}{}, cycle {} µs, cable redundancy {}", settings_.name,
                settings_.eni_path, eni_->slaves.size(), settings_.main_interface,
                red_link_ ? fmt::format(", RED {}", settings_.red_interface) : std::string(),
                cycle_time().count(), settings_.cable_redundancy ? "on" : "off");
    return kOk;
}

void Daemon::start_threads() {
    // A single master reads its links in its cycle (receive_in_cycle); a
    // pair member's receive threads take frames while it forwards in user space.
    if (reception_) reception_->start();
    cycle_thread_->start();
    if (tap_bridge_) tap_bridge_->start();

    event_thread_ = std::thread([this] { pump_events(); });
}

void Daemon::stop_threads() {
    stopping_ = true;
    topology_verifier_.reset();
    slave_monitor_.reset();
    mailbox_service_.reset();  // fails what is queued, waits for the running transfers
    // Hot-Connect and the state machine call each other: cut that, then stop the machine first.
    if (hot_connect_) hot_connect_->set_presence_listener({});
    state_machine_.reset();  // cancels a running sequence (its requests fail when the cycle stops)
    hot_connect_.reset();
    if (cycle_thread_) cycle_thread_->stop();
    if (reception_) reception_->stop();
    if (tap_bridge_) tap_bridge_->stop();
    if (event_thread_.joinable()) event_thread_.join();
}

void Daemon::pump_events() {
    while (!stopping_.load()) {
        for (const auto& report : events_.pop_all(std::chrono::milliseconds(200))) {
            auto message = to_message(report, *describer_);
            log()->info("event {}: {}", message.kind(), message.text());
            boost::asio::post(io_, [this, message = std::move(message)] { control_server_->publish(message); });
        }
    }
}

void Daemon::watch_links() {
    link_fd_->async_wait(boost::asio::posix::stream_descriptor::wait_read, [this](const boost::system::error_code& ec) {
        if (ec) return;
        const auto changes = link_monitor_->read_changes();
        const auto role_of = [this](const link::LinkStateChange& change) {
            return change.interface == settings_.main_interface ? master::LinkRole::Main : master::LinkRole::Red;
        };
        // What the supervisor reads first, for every change read together:
        // both links going down at once (a link guard) must be one loss at
        // the next cycle boundary, not MAIN down with RED up for the cycles
        // the slower part below takes; that looks like a partner failure
        // (a link loss shortens the comm timeout) and would take over.
        for (const auto& change : changes) master_->set_link_state(role_of(change), change.up);
        for (const auto& change : changes) {
            const auto role = role_of(change);
            log()->info("link {} ({}) {}", master::to_string(role), change.interface, change.up ? "up" : "down");
            if (redundancy_) redundancy_->set_link_state(role, change.up);  // store-and-forward, the kernel program
        }
        watch_links();
    });
}

int Daemon::open_redundancy() {
    if (!settings_.redundancy.enabled) return kOk;
    const auto& r = settings_.redundancy;
    redundancy::RedundancyOptions options;
    options.partner_silence = r.partner_silence;
    auto& p = options.parameters;
    p.eni_content_hash = eni_->content_hash;
    p.cycle_time = master_->options().cycle_time;
    p.cable_redundancy = settings_.cable_redundancy;
    p.split_lrw = settings_.split_lrw;
    p.master_pd_out_size = r.master_pd_out_size;
    p.master_pd_in_size = r.master_pd_in_size;
    p.update_slave_pd_in = r.update_slave_pd_in;
    p.update_slave_pd_out = r.update_slave_pd_out;
    p.max_acyc_frames_per_cycle = static_cast<std::uint16_t>(settings_.max_acyclic_frames_per_cycle);
    auto created = redundancy::RedundancyController::create(*master_, options, events_);
    if (!created) {
        log()->error("{}", created.error());
        return kBadConfig;
    }
    redundancy_ = std::move(*created);
    redundancy_->set_on_role_change([this](const redundancy::RoleChange& change) { on_role_change(change); });

    supervisor::SupervisorOptions decisions;
    decisions.cycle_time = master_->options().cycle_time;
    decisions.comm_timeout = r.comm_timeout;
    decisions.partner_silence = r.partner_silence;
    decisions.start_active = r.start_active;
    decisions.start_in_forced_standby = r.start_in_forced_standby;
    decisions.takeover_from_differing_partner = r.takeover_from_differing_partner;
    decisions.arbitration.listen_time = r.listen_time;
    decisions.arbitration.backoff_min = r.backoff_min;
    decisions.arbitration.backoff_max = r.backoff_max;
    supervisor_ = std::make_unique<supervisor::Supervisor>(decisions, random_, events_);
    redundancy_->set_role_decider(supervisor_.get());
    topology_verifier_ = std::make_unique<redundancy::TopologyVerifier>(eni_, master_->bus(), events_);
    if (settings_.tap) {
        auto bridge = tap_bridge::TapBridge::open(*settings_.tap);
        if (!bridge) {
            log()->error("{}", bridge.error());
            return kLinkFailure;
        }
        tap_bridge_ = std::move(*bridge);
        redundancy_->set_acyclic_channel(&tap_bridge_->channel());
    }
    auto forwarding = open_forwarding_path(settings_);
    if (!forwarding) {
        log()->error("{}", forwarding.error());
        return kLinkFailure;
    }
    redundancy_->set_kernel_forwarding(std::move(*forwarding));
    // Just below the cycle: a frame to forward must leave before anything else.
    reception_ = std::make_unique<redundancy::PairReception>(*main_link_, *red_link_, *redundancy_,
                                                             std::max(settings_.realtime_priority - 1, 0));
    return kOk;
}

// Hot-Connect follows the bus from the first startup scan on; an INACTIVE
// pair member follows the mirrored image until it takes over.
void Daemon::open_hot_connect() {
    hotconnect::HotConnectOptions options;
    const auto& h = settings_.hot_connect;
    options.mode = h.mode == config::HotConnectMode::ManualPreop     ? hotconnect::HotConnectMode::ManualPreop
                   : h.mode == config::HotConnectMode::ManualNoReset ? hotconnect::HotConnectMode::ManualNoReset
                                                                     : hotconnect::HotConnectMode::Automatic;
    options.border_close = h.border_close;
    options.detection_timeout = h.detection_timeout;
    hot_connect_host_ = std::make_unique<hotconnect::MasterHost>(*master_);
    hot_connect_ = std::make_unique<hotconnect::HotConnect>(eni_, *hot_connect_host_, &events_, options);
    hot_connect_service_ = std::make_unique<HotConnectService>(*hot_connect_);
    if (settings_.redundancy.enabled && !settings_.redundancy.start_active) hot_connect_->set_active(false);
}

// On the state machine's worker thread. A master keeps trying to bring its
// bus up: a failed start (a scan that found nobody, a slave missing, a
// command that timed out) is tried again a little later, until it works or
// the target changes. An INACTIVE master or a shutdown ends it quietly.
void Daemon::on_sequence_done(const sequencer::SequenceResult& result) {
    hot_connect_->on_sequence_idle(result.reached, !result.error && result.reached == result.target);
    if (!result.error) {
        log()->info("slaves in {}", sequencer::to_string(result.reached));
        return;
    }
    log()->error("state machine stopped in {} (target {}): {}", sequencer::to_string(result.reached),
                 sequencer::to_string(result.target), result.error->message);
    switch (result.error->failure) {
        case sequencer::SequenceFailure::MasterInactive:
        case sequencer::SequenceFailure::Cancelled:
        case sequencer::SequenceFailure::Stopped: return;
        default: break;
    }
    boost::asio::post(io_, [this, target = result.target] {
        retry_timer_.expires_after(kSequenceRetry);
        retry_timer_.async_wait([this, target](const boost::system::error_code& ec) {
            if (ec || stopping_ || state_machine_->busy() || state_machine_->target() != target) return;
            if (redundancy_ && redundancy_->state() != redundancy::RedState::Active) return;
            log()->info("trying {} again", sequencer::to_string(target));
            state_machine_->request(target);
        });
    });
}

// On the cycle thread, at the boundary where the role changed: hand the work
// to the control thread at once.
void Daemon::on_role_change(const redundancy::RoleChange& change) {
    boost::asio::post(io_, [this, change] {
        if (change.to == redundancy::RedState::Inactive) {
            hot_connect_->set_active(false);
            return;  // sequences stop on their own (bus refused)
        }
        const auto target = *sequencer::to_master_state(settings_.target_state);
        // Mailbox messages go on from where the partner's counters stopped.
        state_machine_->continue_mailbox_counters(redundancy_->partner_mailbox_counters());
        if (change.hot) {
            const auto state = sequencer::to_master_state(change.master_state);
            if (state) state_machine_->adopt(*state);
            topology_verifier_->verify(master_->slaves().snapshot());
            // A topology change the partner had under way is finished here.
            hot_connect_->after_takeover();
            // Taken over during a transition (start-up, a state change): finish it here.
            if (state != target) state_machine_->request(target);
        } else {
            hot_connect_->set_active(true);
            state_machine_->request(target);
        }
    });
}

// The application of the cycle: the demo, and in a pair the master-to-master
// process data (the ACTIVE sends its cycle counter, the INACTIVE echoes what it got).
void Daemon::on_cycle(master::ProcessImage& image, const master::CycleInfo& info) {
    demo_->on_cycle(image, info);
    if (!redundancy_) return;
    if (info.sending) {
        auto out = redundancy_->master_pd_out();
        for (std::size_t i = 0; i < out.size() && i < 8; ++i) out[i] = static_cast<std::uint8_t>(info.cycle >> (8 * i));
    } else {
        redundancy_->set_master_pd_in(redundancy_->received_master_pd_out());
    }
}

int Daemon::run() {
    start_threads();
    // A pair member starts INACTIVE: its supervisor decides when it owns the bus
    // (the role change then starts the state machine).
    if (!redundancy_) state_machine_->request(*sequencer::to_master_state(settings_.target_state));

    if (link_guard_) link_guard_->start_heartbeat();
    service_notifier_ = systemd::ServiceNotifier::from_environment(io_, [this] { return master_->cycle(); },
                                                                    [this] { return service_status(); });

    boost::asio::signal_set signals(io_, SIGINT, SIGTERM);
    signals.async_wait([this](const boost::system::error_code& ec, int signal) {
        if (!ec) log()->info("signal {}: stopping", signal);
        service_notifier_->stopping();
        io_.stop();
    });
    // The monitor keeps its fd; asio must not close it.
    link_fd_.emplace(io_, ::dup(link_monitor_->selectable_fd()));
    watch_links();
    service_notifier_->ready();
    io_.run();

    const auto timing = cycle_thread_->timing();
    const auto stats = master_->stats();
    stop_threads();
    if (link_guard_) link_guard_->shutdown();  // stopped sending: now the links go down
    log()->info("{} cycles ({} late, {} skipped, wake-up latency p99 {} µs, max {} µs), {} frames sent, {} lost, "
                "{} late copies ({} on RED), {} incomplete cycles, {} WKC errors",
                timing.cycles, timing.late, timing.skipped, timing.latency_percentile_us(99.0),
                std::chrono::duration_cast<std::chrono::microseconds>(timing.max_wake_latency).count(),
                stats.frames_sent, stats.frames_lost, stats.late_frames, stats.late_frames_on_red,
                stats.cycles_incomplete, stats.wkc_errors);
    if (settings_.demo == config::DemoKind::LoopbackCheck) {
        const auto loop = demo_->stats();
        log()->info("loopback check: {} cycles in OP checked, {} slave checks, {} mismatches", loop.cycles_checked,
                    loop.slaves_checked, loop.mismatches);
    }
    return kOk;
}

}  // namespace ecpair::daemon
