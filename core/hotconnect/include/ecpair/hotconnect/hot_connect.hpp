#pragma once
// Hot-Connect for one master (hot-connect.md): groups that come and go
// while the bus runs. A worker thread of its own runs the topology change
// state machine (topology_change.hpp) whenever the bus changes:
//
//   detect   the cycle's topology watch (the AL-status BRD counted other
//            slaves), a periodic count of the slaves (every poll period,
//            one BRD), or an operator's "force";
//   settle   the slave count must hold still (two reads settle_gap apart)
//            within the detection timeout;
//   scan     positions, station addresses, DL and AL status; SII only of
//            slaves not known (hot_connect_scan.hpp);
//   identify the bus against the ENI (bus::match_topology): groups present,
//            gone, refused; mismatch descriptors; presence per slave;
//   correct  the expected WKCs of the cyclic datagrams (wkc_contributions):
//            groups gone count no more, the slaves found answer the BRD;
//   report   SlavePresence, BusScanStatus, BusMismatch (+ identification,
//            + where it hangs), DetectAddGroups / ProbeAllGroups;
//   bring up new groups to the master state (group_bring_up.hpp) -- in the
//            manual modes after an accept -- counting them in the WKCs once
//            in SAFEOP;
//   close    border close (port_control.hpp) when configured;
//   done     TopologyChangeDone with the result, once per change; the watch
//            is settled, so deviations from now on are cyclic WKC errors.
//
// It acts only while the master state machine is idle at its target (PREOP
// or above) and the master is ACTIVE; an INACTIVE master follows the
// mirrored slave state image instead (its expected WKCs are kept in step so
// that a takeover needs no correction), and a new ACTIVE finishes a change
// the image shows in progress. Operations (accept, force, block node, open
// blocked ports, port settings, programming the alias) are serialised with
// the worker's bus work.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "ecpair/bus/topology_match.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/hotconnect/hot_connect_events.hpp"
#include "ecpair/hotconnect/hot_connect_host.hpp"
#include "ecpair/hotconnect/hot_connect_view.hpp"
#include "ecpair/hotconnect/port_control.hpp"
#include "ecpair/hotconnect/topology_change.hpp"
#include "ecpair/hotconnect/wkc_contributions.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/startup_scan.hpp"
#include "ecpair/sequencer/transition_plan.hpp"

namespace ecpair::hotconnect {

struct HotConnectOptions {
    HotConnectMode mode = HotConnectMode::Automatic;
    bool border_close = false;
    std::chrono::milliseconds detection_timeout{15000};
    std::chrono::milliseconds poll_period{100};
    std::chrono::milliseconds settle_gap{5};
};

enum class OperationError : std::uint8_t { InvalidState, InvalidParam, SlaveNotPresent, NotFound, MasterRedStateInactive, Failed };
std::string_view to_string(OperationError error);

struct OperationFailure {
    OperationError code = OperationError::Failed;
    std::string message;
};

struct HotConnectStatus {
    bool active = true;
    ChangeState state = ChangeState::Idle;
    HotConnectOptions options;
    std::vector<GroupView> groups;
    std::vector<MismatchView> mismatches;
    std::vector<PortRef> blocked;
    std::optional<TopologyResult> last_result;
    std::uint64_t changes = 0;
    std::uint16_t slaves_on_bus = 0;
};

class HotConnect {
public:
    // Called (on the worker) whenever Hot-Connect changed which slaves take
    // part and where they are: the master state machine's next transitions use it.
    using PresenceListener = std::function<void(const std::vector<bool>& present, const std::vector<std::uint16_t>& shift)>;

    HotConnect(std::shared_ptr<const eni::EniConfig> eni, HotConnectHost& host, master::EventQueue* events,
               HotConnectOptions options = {}, sequencer::Clock& clock = sequencer::steady_clock());
    ~HotConnect();
    HotConnect(const HotConnect&) = delete;
    HotConnect& operator=(const HotConnect&) = delete;

    void set_presence_listener(PresenceListener listener);

    // ---- from the master state machine (its worker thread)
    // The startup scan: what is on the bus; corrects the expected WKCs before the first state goes out.
    void on_startup_scan(const sequencer::ScanOutcome& outcome);
    // A sequence started (busy) or the machine is idle at `reached` (the target, or short of it).
    void on_sequence_busy();
    void on_sequence_idle(sequencer::MasterState reached, bool at_target);

    // ---- redundancy (any thread)
    void set_active(bool active);
    // Became ACTIVE from a mirror: finish a change the image shows in progress.
    void after_takeover();

    // ---- operations (any thread; they wait for bus work in progress)
    Expected<void, OperationFailure> accept();
    Expected<void, OperationFailure> force_topology_change();
    // Closes the port in front of mismatch `index` of status().mismatches
    // (nullopt: the first), or in front of the slave with `station`.
    Expected<PortRef, OperationFailure> block_node(std::optional<std::size_t> mismatch, std::optional<std::uint16_t> station);
    Expected<std::vector<PortRef>, OperationFailure> open_blocked_ports();
    Expected<void, OperationFailure> set_port(std::uint16_t station, int port, LoopSetting setting);
    // Programs the station alias into the slave's SII (taken over at its next power-on); the alias it had.
    Expected<std::uint16_t, OperationFailure> set_alias(std::uint16_t station, std::uint16_t alias);

    HotConnectStatus status() const;
    // For tests: waits until no topology change is in progress (or AwaitingAccept), true when so.
    bool wait_idle(std::chrono::milliseconds timeout) const;

private:
    void worker(std::stop_token stop);
    void handle(bool detected, bool accepted, bool takeover, bool close, std::stop_token stop);
    bool periodic_count_changed();
    void enable_dl_status_events();
    void follow_image();
    void advance(ChangeInput input);
    void run_change(std::stop_token stop);
    std::optional<std::uint16_t> settle(std::stop_token stop);
    void bring_up_pending(sequencer::MasterState target, bool reset_first, std::stop_token stop);
    void close_borders();
    void finish(TopologyResult result);

    void apply_match(const bus::ScanReport& report, const bus::TopologyMatch& match, bool report_events);
    void publish_expected_wkcs();
    void write_flags();
    void notify_presence();
    void raise(master::EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0, std::uint32_t d = 0);
    std::optional<OperationFailure> refusal() const;
    const master::SlaveStateEntry* entry_of_station(std::uint16_t station, master::SlaveStateEntry& storage) const;
    std::optional<std::size_t> slave_of_station(std::uint16_t station) const;

    std::shared_ptr<const eni::EniConfig> eni_;
    eni::HotConnectGroups groups_;
    HotConnectHost& host_;
    master::EventQueue* events_;
    HotConnectOptions options_;
    sequencer::Clock& clock_;
    WkcContributions contributions_;
    std::uint16_t event_mask_;  // ECAT event mask 0x0200 for every slave (the ENI's, plus the DL status event)
    PresenceListener presence_listener_;

    // Bus work (the worker's changes and the operations) one at a time.
    std::mutex bus_work_;

    // Guarded by mutex_ (short holds only: the cycle thread notifies through it).
    mutable std::mutex mutex_;
    mutable std::condition_variable_any wake_;
    bool detected_ = false;                     // an operator's force
    std::atomic<bool> cycle_detected_{false};   // the cycle's topology watch (set without the lock)
    bool accepted_ = false;
    bool takeover_ = false;       // became ACTIVE: finish what the image shows in progress
    bool close_pending_ = false;  // border close to run once the bus is up
    bool events_pending_ = false; // the slaves' DL status events to enable
    bool working_ = false;        // the worker is handling what it was woken for
    bool armed_ = false;   // the master state machine is idle at its target
    bool active_ = true;
    sequencer::MasterState master_state_ = sequencer::MasterState::Init;
    ChangeState state_ = ChangeState::Idle;
    std::optional<TopologyResult> last_result_;
    std::uint64_t changes_ = 0;
    std::vector<MismatchView> mismatches_;
    std::vector<PortRef> blocked_;
    std::set<std::pair<std::uint16_t, int>> border_closed_;

    // What Hot-Connect knows of the bus (worker, and operations under bus_work_).
    bool baseline_ = false;
    std::vector<bool> present_;         // identified and taking part
    std::vector<bool> counted_;         // exchanging process data (present and at least SAFEOP)
    std::vector<std::uint8_t> flags_;   // master::kGroupPresent...
    std::vector<std::uint16_t> shift_;  // configured minus found position
    std::vector<bool> group_up_;        // per group: in the master state
    std::vector<std::size_t> pending_;  // groups found, not yet brought up
    std::atomic<std::uint16_t> answering_{0};  // slaves answering a BRD (read by status())
    std::optional<bus::ScanReport> last_report_;
    std::optional<bus::TopologyMatch> last_match_;
    bool groups_added_ = false;
    bool groups_removed_ = false;
    TopologyResult change_result_ = TopologyResult::Ok;
    std::uint64_t deviations_at_start_ = 0;
    sequencer::Clock::time_point change_started_{};
    std::vector<std::optional<std::uint16_t>> followed_;  // INACTIVE: the expected WKCs last published

    std::jthread thread_;  // last
};

}  // namespace ecpair::hotconnect
