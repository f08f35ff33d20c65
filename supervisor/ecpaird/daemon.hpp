#pragma once
// ecpaird's composition for one controller: the validated settings, the
// ENI, the links, the cyclic master with its cycle and receive threads, the
// state machine that drives the slaves to the target state, the demo
// application, and the control thread (Boost.Asio) with signals, link state
// changes and event logging. design.md §4 names the threads.

#include <memory>
#include <optional>
#include <thread>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

#include "demo_application.hpp"
#include "ecpair/control/control_server.hpp"
#include "ecpair/config/daemon_settings.hpp"
#include "ecpair/hotconnect/hot_connect.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/link/link_state_monitor.hpp"
#include "ecpair/linkguard/link_guard.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "ecpair/master/cycle_thread.hpp"
#include "ecpair/master/event_describer.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/redundancy/pair_reception.hpp"
#include "ecpair/redundancy/redundancy_controller.hpp"
#include "ecpair/redundancy/topology_verifier.hpp"
#include "ecpair/sequencer/mailbox_service.hpp"
#include "ecpair/sequencer/master_state_machine.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sequencer/slave_monitor.hpp"
#include "ecpair/arbitration/random_source.hpp"
#include "ecpair/supervisor/supervisor.hpp"
#include "ecpair/tap_bridge/tap_bridge.hpp"
#include "ecpair/systemd/service_notifier.hpp"
#include "link_guard_resume_policy.hpp"
#include "operator_service.hpp"

namespace ecpair::daemon {

class Daemon {
public:
    // Exit codes of ecpaird.
    static constexpr int kOk = 0;
    static constexpr int kBadConfig = 2;
    static constexpr int kLinkFailure = 3;

    explicit Daemon(config::DaemonSettings settings);
    ~Daemon();

    // Opens everything; a non-zero exit code (and a logged reason) on failure.
    int open();
    // Runs until SIGINT/SIGTERM.
    int run();

private:
    void start_threads();
    void stop_threads();
    void watch_links();
    void pump_events();
    std::chrono::microseconds cycle_time() const;
    int open_links();
    int open_redundancy();
    void open_hot_connect();
    int open_link_guard();          // daemon_ops.cpp
    std::unique_ptr<LinkGuardResumePolicy> make_link_guard_policy();  // daemon_ops.cpp
    std::string service_status() const;  // daemon_ops.cpp: one line for systemd
    void on_role_change(const redundancy::RoleChange& change);
    void on_sequence_done(const sequencer::SequenceResult& result);
    void on_cycle(master::ProcessImage& image, const master::CycleInfo& info);

    config::DaemonSettings settings_;
    std::shared_ptr<const eni::EniConfig> eni_;
    std::unique_ptr<link::PcapLink> main_link_;
    std::unique_ptr<link::PcapLink> red_link_;
    std::unique_ptr<link::LinkStateMonitor> link_monitor_;
    master::EventQueue events_;
    std::unique_ptr<master::Master> master_;
    std::unique_ptr<master::EventDescriber> describer_;  // event texts for the log and the operator API
    std::unique_ptr<DemoApplication> demo_;
    // The slaves' mailboxes, shared by the state machine's InitCmds and the mailbox service.
    std::unique_ptr<sequencer::SlaveMailboxes> mailboxes_;
    std::unique_ptr<sequencer::MasterStateMachine> state_machine_;
    std::unique_ptr<sequencer::MailboxService> mailbox_service_;  // CoE emergencies as events (docs/MAILBOX.md)
    std::unique_ptr<sequencer::SlaveMonitor> slave_monitor_;
    std::unique_ptr<hotconnect::MasterHost> hot_connect_host_;
    std::unique_ptr<hotconnect::HotConnect> hot_connect_;
    std::unique_ptr<HotConnectService> hot_connect_service_;
    std::unique_ptr<tap_bridge::TapBridge> tap_bridge_;  // only with a tap block; outlives the controller
    std::unique_ptr<redundancy::RedundancyController> redundancy_;  // only in a redundant pair
    arbitration::SystemRandom random_;
    std::unique_ptr<supervisor::Supervisor> supervisor_;            // decides the pair member's role
    std::unique_ptr<redundancy::TopologyVerifier> topology_verifier_;
    std::unique_ptr<master::CycleThread> cycle_thread_;
    std::unique_ptr<redundancy::PairReception> reception_;  // only in a redundant pair

    boost::asio::io_context io_;
    static constexpr std::chrono::seconds kSequenceRetry{2};
    boost::asio::steady_timer retry_timer_{io_};
    std::unique_ptr<OperatorService> operator_service_;
    std::unique_ptr<control::ControlServer> control_server_;
    std::optional<boost::asio::posix::stream_descriptor> link_fd_;
    std::thread event_thread_;
    std::atomic<bool> stopping_{false};

    // Operations (daemon_ops.cpp): after io_, which they use.
    std::unique_ptr<linkguard::LinkGuard> link_guard_;  // only with link_guard.enabled
    std::unique_ptr<LinkGuardResumePolicy> link_guard_policy_;
    std::unique_ptr<systemd::ServiceNotifier> service_notifier_;
};

}  // namespace ecpair::daemon
