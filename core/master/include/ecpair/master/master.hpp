#pragma once
// The master engine, driven by a cycle (the JobTask, design.md §4). Every
// cycle: take the frames that came back since the last cycle (read from the
// links, or handed over through lock-free rings), merge the MAIN and RED
// copies, move inputs into the process image and check working counters;
// run the application's cycle hook; send this cycle's cyclic frames, the
// extension's frames (redundancy) and a bounded number of acyclic frames.
//
// Threads: run_cycle() on the cycle thread only; on_frame() by one thread
// per link at a time (its receive thread, or the cycle thread reading the
// link); everything else is safe from any thread and takes effect at the
// next cycle boundary.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/master/acyclic_queue.hpp"
#include "ecpair/master/cycle_extension.hpp"
#include "ecpair/master/cyclic_exchange.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/master/frame_ring.hpp"
#include "ecpair/master/frame_tracker.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/master/process_image.hpp"
#include "ecpair/master/slave_state_image.hpp"
#include "ecpair/master/topology_watch.hpp"

namespace ecpair::master {

struct MasterOptions {
    std::chrono::nanoseconds cycle_time{std::chrono::milliseconds(1)};
    bool cable_redundancy = false;  // send every frame on MAIN and RED (needs a RED link)
    bool split_lrw = false;         // with cable redundancy: LRW -> LWR + LRD
    std::size_t max_acyclic_frames_per_cycle = 2;
    // The cycle thread reads the links itself at the start of each cycle
    // (accept_returned_frames) instead of taking what on_frame put into its
    // rings: a single master, so that it wakes once a cycle, not once a
    // frame. A pair member's links are read by its PairReception (redundancy),
    // which calls on_frame. on_frame must not be used with this.
    bool receive_in_cycle = false;
};

struct CycleInfo {
    std::uint64_t cycle = 0;
    eni::SlaveState state = eni::SlaveState::Init;
    bool inputs_valid = false;  // every cyclic frame of the last cycle came back complete
    bool sending = true;        // false while passive (an INACTIVE master): the image is not ours to write
};

enum class RingState : std::uint8_t { Unknown, Closed, Broken };
std::string_view to_string(RingState state);

// A copy of the process image as the cycle left it, for other threads.
struct ImageSnapshot {
    std::uint64_t cycle = 0;
    eni::SlaveState state = eni::SlaveState::Init;
    bool inputs_valid = false;
    std::vector<std::uint8_t> inputs;
    std::vector<std::uint8_t> outputs;
};

struct MasterStats {
    std::uint64_t cycles = 0;
    std::uint64_t frames_sent = 0;
    std::uint64_t frames_lost = 0;        // not complete when the next cycle started
    std::uint64_t late_frames = 0;        // copies that came back after their cycle was completed
    std::uint64_t late_frames_on_red = 0;  // of those, the ones that arrived on RED (the rest on MAIN)
    std::uint64_t cycles_incomplete = 0;  // some cyclic data of the cycle is missing
    std::uint64_t wkc_errors = 0;
    std::uint64_t wkc_topology_deviations = 0;  // WKC deviations while the topology changed (Hot-Connect)
    std::uint64_t foreign_frames = 0;
    std::uint64_t send_errors = 0;
    std::uint64_t rx_dropped = 0;
};

namespace detail {
class CycleBatches;
}

class Master {
public:
    using CycleHook = std::function<void(ProcessImage&, const CycleInfo&)>;

    // Fails when the ENI's cyclic frames cannot be used with these options
    // (LRW with cable redundancy) or a RED link is missing for redundancy.
    static Expected<std::unique_ptr<Master>, std::string> create(std::shared_ptr<const eni::EniConfig> eni,
                                                                 const MasterOptions& options, link::Link& main,
                                                                 link::Link* red, EventQueue& events);
    ~Master();

    // ---- cycle thread
    void run_cycle(link::Clock::time_point now);
    ProcessImage& image() { return image_; }

    // ---- one producer per link (see above)
    void on_frame(LinkRole arrived_on, ConstBytes frame, link::Clock::time_point received_at);

    // ---- any thread
    bus::BusAccess& bus() { return acyclic_; }
    AcyclicQueue& acyclic() { return acyclic_; }
    eni::SlaveState state() const { return state_.load(); }
    void request_state(eni::SlaveState state) { requested_state_.store(state); }
    void set_link_state(LinkRole role, bool up);
    void set_sending(bool enabled) { sending_requested_.store(enabled); }
    // The cycle counter (advanced by run_cycle).
    std::uint64_t cycle() const { return cycle_counter_.load(); }
    // While not sending, from the extension's begin_cycle: number the current
    // cycle `cycle` (a standby master counts with the partner it follows, so
    // both name a cycle alike).
    void follow_cycle(std::uint64_t cycle) { cycle_to_follow_.store(cycle); }
    // Slaves that answered the AL-status BRD of the last cycle whose BRD came
    // back (nullopt before that, or when no cyclic frame carries a BRD).
    std::optional<std::uint16_t> slaves_reached() const {
        const auto r = slaves_reached_.load();
        return r < 0 ? std::nullopt : std::optional<std::uint16_t>(static_cast<std::uint16_t>(r));
    }
    // Cycles in a row, up to the last one, in which this master sent and no copy of any frame came back.
    std::uint64_t cycles_without_return() const { return cycles_without_return_.load(); }
    bool sending() const { return sending_.load(); }
    RingState ring_state() const { return ring_state_.load(); }
    // Slaves reachable from MAIN while the ring is broken (from a BRD's WKC), nullopt when unknown.
    std::optional<std::uint16_t> reachable_from_main() const {
        const auto r = reachable_from_main_.load();
        return r < 0 ? std::nullopt : std::optional<std::uint16_t>(static_cast<std::uint16_t>(r));
    }
    MasterStats stats() const;
    // The image of the last completed cycle (copied under a brief lock).
    ImageSnapshot snapshot() const;
    SlaveStateImage& slaves() { return slaves_; }
    const SlaveStateImage& slaves() const { return slaves_; }
    // Hot-Connect: notices bus changes in the cycle; the expected WKCs of the
    // cyclic datagrams (flat, CyclicExchange numbering) for the slaves on the
    // bus now, taken over at the next cycle boundary.
    TopologyWatch& topology_watch() { return topology_watch_; }
    void set_expected_wkcs(std::vector<std::optional<std::uint16_t>> expected);
    const eni::EniConfig& eni() const { return *eni_; }
    bool link_up(LinkRole role) const { return link_up_[static_cast<std::size_t>(role)].load(); }
    const MasterOptions& options() const { return options_; }
    const CyclicPlan& plan() const { return exchange_.plan(); }
    link::Link& link(LinkRole role) { return role == LinkRole::Main ? main_ : *red_; }
    bool has_red() const { return red_ != nullptr; }

    // Set before the cycle thread starts.
    void set_cycle_hook(CycleHook hook) { hook_ = std::move(hook); }
    void set_extension(CycleExtension* extension) { extension_ = extension; }

private:
    class Sender;
    struct InFlight {
        std::uint8_t id;
        FrameKind kind;
        std::uint16_t index;
        bool sent_main;
        bool sent_red;
        std::uint64_t cycle;     // when it was sent
        LostFrameDetail detail;  // what a FrameLost event will say about it
    };

    Master(std::shared_ptr<const eni::EniConfig> eni, const MasterOptions& options, link::Link& main,
           link::Link* red, EventQueue& events, CyclicPlan plan);

    void accept_returned_frames();
    void complete_previous_cycle(link::Clock::time_point now);
    bool is_complete(const InFlight& f, const ReturnedCopy& main_copy, const ReturnedCopy& red_copy,
                     const MergeResult& merged, const wire::ConstFrameView& view) const;
    void observe_ring(bool closed, bool broken, std::optional<std::uint16_t> reachable);
    void apply_followed_cycle();
    void apply_requests();
    void send_frames(link::Clock::time_point now);
    void send_copies(FrameKind kind, std::uint16_t index, Bytes frame, std::uint8_t retry_index = 0);
    bool prepare_red_copy(FrameKind kind, Bytes frame) const;
    // Queues a copy for the link's batch (owner: its sent_this_cycle_ entry);
    // send_queued() sends the batches and marks each copy sent or not.
    void queue_copy(LinkRole role, ConstBytes frame, std::size_t owner);
    void send_queued();
    void receive_from_links();
    void accept_copy(LinkRole role, ConstBytes frame);
    void raise(EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0, std::uint32_t d = 0);
    void publish_snapshot();
    bool use_red() const;

    std::shared_ptr<const eni::EniConfig> eni_;
    MasterOptions options_;
    link::Link& main_;
    link::Link* red_;
    EventQueue& events_;

    CyclicExchange exchange_;
    ProcessImage image_;
    FrameTracker tracker_;
    AcyclicQueue acyclic_;
    std::array<FrameRing, 2> rx_rings_;
    CycleHook hook_;
    CycleExtension* extension_ = nullptr;
    SlaveStateImage slaves_;
    TopologyWatch topology_watch_;

    // Cycle-thread state.
    std::uint64_t cycle_ = 0;
    std::vector<InFlight> in_flight_;       // frames sent in the previous cycle (and acyclic ones still awaited)
    std::uint64_t acyclic_patience_ = 2;   // cycles an acyclic frame may take to come back
    std::vector<InFlight> sent_this_cycle_;
    std::vector<WkcMismatch> mismatches_;
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> tx_{};
    std::unique_ptr<detail::CycleBatches> tx_batches_;
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan + 64> rx_{};  // receive_in_cycle
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> merged_{};
    bool inputs_valid_ = false;
    std::uint64_t foreign_reported_cycle_ = UINT64_MAX;

    // Shared with other threads.
    mutable std::mutex snapshot_mutex_;  // the cycle only try_locks it
    ImageSnapshot snapshot_;
    std::mutex expected_mutex_;  // the cycle only try_locks it
    std::vector<std::optional<std::uint16_t>> expected_wkcs_;
    std::atomic<bool> expected_wkcs_pending_{false};
    std::atomic<eni::SlaveState> state_{eni::SlaveState::Init};
    std::atomic<eni::SlaveState> requested_state_{eni::SlaveState::Init};
    std::atomic<std::uint64_t> cycle_counter_{0};
    std::atomic<bool> sending_{true};
    std::atomic<bool> sending_requested_{true};
    std::array<std::atomic<bool>, 2> link_up_{};
    std::atomic<RingState> ring_state_{RingState::Unknown};
    static constexpr std::int32_t kReachableUnknown = -1;
    std::atomic<std::int32_t> reachable_from_main_{kReachableUnknown};
    std::atomic<std::uint64_t> cycle_to_follow_{0};  // 0: none requested
    std::atomic<std::int32_t> slaves_reached_{-1};
    std::atomic<std::uint64_t> cycles_without_return_{0};
    struct AtomicStats {
        std::atomic<std::uint64_t> cycles{0}, frames_sent{0}, frames_lost{0}, cycles_incomplete{0}, wkc_errors{0},
            foreign_frames{0}, send_errors{0}, late_frames{0}, late_frames_on_red{0}, wkc_topology_deviations{0};
    } stats_;
};

}  // namespace ecpair::master
