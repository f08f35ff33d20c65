#pragma once
// One master of a redundant pair (design.md §1, §4). The controller decides
// what the master's frames and images are for in each role:
//
//   ACTIVE    the master owns the bus; after its cyclic slave frames the
//             controller sends the Cyclic Master Red Frame (CMF) on MAIN and
//             RED and reads the partner's answer from its returns.
//   INACTIVE  the master sends nothing and refuses to talk to slaves; every
//             frame that arrives is forwarded at once (StoreAndForward), the
//             CMF processed on the way, and the mirror brings the ACTIVE's
//             state, slave state image and process image into this master
//             every cycle (hot standby).
//
// Who decides the role: a RoleDecider (the Supervisor) when one is set,
// asked at every cycle boundary with what the controller saw; otherwise
// explicit requests (request()). Either way a change takes effect at the
// next cycle boundary (begin_cycle); asking for the current role does
// nothing.
//
// What the controller adds to the CMF for its decider (docs/WIRE_FORMAT.md):
// as ACTIVE its epoch, reach, MAIN MAC, send offset and a hand-off
// announcement in the header; as INACTIVE its standby status, filled into
// every CMF it forwards, acknowledging an announced hand-off when the
// decider says it is ready. While INACTIVE the master counts cycles with
// the partner's numbering and, through phase_reference(), runs its cycle in
// step with the partner's (so that a hand-off needs no extra cycle). Becoming ACTIVE from a fresh
// mirror is a hot takeover: process data goes out from the mirrored image in
// that same cycle, the slaves keep their state, and the topology is known
// from the mirrored slave state image (a background scan verifies it).
// Giving up ACTIVE stops all sending at the next boundary and fails the
// pending acyclic requests with MasterRedStateInactive.

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/master/cycle_extension.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/redundancy/acyclic_master_red_channel.hpp"
#include "ecpair/redundancy/cmf_writer.hpp"
#include "ecpair/redundancy/image_history.hpp"
#include "ecpair/redundancy/kernel_forwarding.hpp"
#include "ecpair/redundancy/pair_parameters.hpp"
#include "ecpair/redundancy/role_decider.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace ecpair::redundancy {

class Mirror;
struct MirroredCycle;
class MailboxCounterMirror;

struct RedundancyOptions {
    bool start_active = false;
    PairParameters parameters;  // what this master and its partner must agree on
    // A mirror older than this is no basis for a hot takeover (then: cold
    // start from INIT). Generous: a hot takeover from an older mirror is
    // verified by the background scan and the slave monitor, while a cold
    // start would take every slave through INIT.
    std::chrono::milliseconds mirror_fresh{5000};
    // The ACTIVE calls its partner lost after this long without an answer in the CMF.
    std::chrono::milliseconds partner_silence{100};
};

// Where a standby master's cycle should be: the partner's cycle start, as
// estimated from the arrival of its CMF headers, plus this lag, so that the
// standby's boundary comes just after the partner's.
inline constexpr std::int64_t kPhaseLagDivisor = 16;  // lag = cycle time / 16

// Who forwards the INACTIVE's frames: StoreAndForward in user space, or
// KernelForwarding's program (user space then only mirrors).
enum class ForwardingPath : std::uint8_t { User, Kernel };
std::string_view to_string(ForwardingPath path);

struct RoleChange {
    RedState from;
    RedState to;
    bool hot = false;                                      // took over from a fresh mirror
    eni::SlaveState master_state = eni::SlaveState::Init;  // the mirrored state (hot takeover)
};

struct RedundancySnapshot {
    RedState state = RedState::Inactive;
    bool partner_seen = false;
    std::optional<std::string> partner_mismatch;
    std::uint64_t mirrored_cycle = 0;
    std::optional<HeardActive> heard;                // the newest CMF header of another master
    std::optional<CmfStandbyStatus> partner_status;  // ACTIVE: the partner's newest standby status
    std::optional<SteadyTime> partner_last_answer;   // ACTIVE
    std::optional<SteadyTime> last_cmf_completed;    // INACTIVE
    std::uint32_t epoch = 0;
    std::optional<std::uint64_t> handoff_cycle;      // ACTIVE: announced; INACTIVE: acknowledged
    std::vector<std::uint8_t> master_pd_out;  // ACTIVE: sent; INACTIVE: received
    std::vector<std::uint8_t> master_pd_in;   // ACTIVE: received; INACTIVE: sent
    StoreAndForwardCounters forwarding;  // both paths' counts added up
    ForwardingPath forwarding_path = ForwardingPath::User;  // INACTIVE: the path forwarding now
};

class RedundancyController final : public master::CycleExtension {
public:
    static Expected<std::unique_ptr<RedundancyController>, std::string> create(master::Master& master,
                                                                              const RedundancyOptions& options,
                                                                              master::EventQueue& events);
    ~RedundancyController() override;

    // ---- any thread
    void request(RedState state);
    RedState state() const { return state_.load(); }
    // Set before the cycle runs; from then on it decides the role (request() is not used).
    void set_role_decider(RoleDecider* decider) { decider_ = decider; }
    // INACTIVE: a boundary of the partner's cycle schedule for the cycle
    // thread's PhaseLock; nullopt while ACTIVE or without fresh CMF headers.
    std::optional<link::Clock::time_point> phase_reference() const;
    // The mailbox counter the partner used last per slave (ENI order, 0: none
    // seen), for a new ACTIVE to continue after (MasterStateMachine).
    std::vector<std::uint8_t> partner_mailbox_counters() const;
    RedundancySnapshot snapshot() const;
    const ImageHistory& history() const { return history_; }
    // Called on the cycle thread right after a role change took effect; must not block.
    void set_on_role_change(std::function<void(const RoleChange&)> callback) { on_role_change_ = std::move(callback); }
    // Master-to-master traffic after the CMF (the TAP bridge); set before frames flow, outlives the controller.
    void set_acyclic_channel(AcyclicMasterRedChannel* channel);
    // The kernel path for the INACTIVE's frames, attached already: it forwards
    // whenever this master is INACTIVE (now, if it is) and is switched off
    // before the master sends as ACTIVE. Not attached: StoreAndForward
    // forwards. Set before frames flow.
    void set_kernel_forwarding(std::unique_ptr<KernelForwarding> kernel);

    // ---- every frame of a link goes through here: from its receive thread,
    // or from the cycle thread reading the link once a cycle (PairReception)
    void on_frame(master::LinkRole arrived_on, ConstBytes frame, link::Clock::time_point received_at);
    // INACTIVE with StoreAndForward in user space: every frame needs its
    // reaction (forwarding) the moment it arrives.
    bool forwards_in_user_space() const {
        return state_.load(std::memory_order_acquire) == RedState::Inactive &&
               !kernel_forwarding_.load(std::memory_order_acquire);
    }
    void set_link_state(master::LinkRole role, bool up);

    // ---- cycle thread (the application's hook)
    // ACTIVE: the bytes it sends its partner this cycle / the partner's last answer.
    Bytes master_pd_out() { return master_pd_out_; }
    ConstBytes master_pd_in() const { return master_pd_in_; }
    // INACTIVE: what the ACTIVE sent last / what to answer.
    ConstBytes received_master_pd_out() const;
    void set_master_pd_in(ConstBytes data);

    // ---- master::CycleExtension (cycle thread)
    void begin_cycle(master::ProcessImage& image, std::uint64_t cycle, link::Clock::time_point cycle_start) override;
    void send_frames(master::FrameSender& sender, std::uint64_t cycle) override;
    void complete(std::uint16_t index, const master::ReturnedCopy& main_copy,
                  const master::ReturnedCopy& red_copy) override;
    void foreign_frame(master::LinkRole arrived_on, ConstBytes frame) override;

private:
    RedundancyController(master::Master& master, const RedundancyOptions& options, master::EventQueue& events,
                         CmfPlan plan);

    void change_role(RedState to, master::ProcessImage& image);
    void apply_mirror(master::ProcessImage& image);
    bool mirror_fresh() const;
    void read_partner_answer(ConstBytes frame);
    void raise(master::EventKind kind, std::uint32_t a = 0, std::uint32_t b = 0, std::uint32_t c = 0);
    PairObservation observe() const;
    void apply(const RoleDecision& decision, master::ProcessImage& image);
    void publish_status();
    // Receive threads (INACTIVE) and the cycle thread (ACTIVE, foreign frames):
    // remembers a CMF header of another master; returns it.
    std::optional<CmfHeader> note_header(const wire::ConstFrameView& frame, SteadyTime at);
    CmfStandbyStatus standby_status() const;
    // INACTIVE with the kernel path: what user space still does with a frame the kernel forwards.
    void observe_forwarded(master::LinkRole arrived_on, ConstBytes frame, SteadyTime at);
    void start_kernel_forwarding();
    void publish_kernel_answer();  // any thread

    master::Master& master_;
    RedundancyOptions options_;
    master::EventQueue& events_;
    RoleDecider* decider_ = nullptr;
    const wire::MacAddress member_;  // our MAIN adapter
    CmfWriter writer_;
    ImageHistory history_;
    std::unique_ptr<Mirror> mirror_;
    std::unique_ptr<MailboxCounterMirror> mailbox_counters_;
    StoreAndForward forwarding_;
    std::unique_ptr<KernelForwarding> kernel_;
    std::atomic<bool> kernel_forwarding_{false};  // the kernel forwards now (user space does not)

    std::atomic<RedState> state_{RedState::Inactive};
    std::atomic<RedState> requested_{RedState::Inactive};
    std::function<void(const RoleChange&)> on_role_change_;
    AcyclicMasterRedChannel* channel_ = nullptr;

    // Cycle thread.
    master::ProcessImage* image_ = nullptr;
    std::uint64_t cycle_ = 0;
    link::Clock::time_point cycle_start_{};
    std::uint64_t followed_cycle_ = 0;  // the mirrored cycle the master's count last followed
    std::uint32_t epoch_ = 0;
    std::optional<std::uint64_t> announced_handoff_;
    bool announced_committed_ = false;
    struct LeftBus {
        SteadyTime at;
        eni::SlaveState master_state;
    };
    std::optional<LeftBus> left_bus_;  // when this master last stopped being ACTIVE, and where it left the slaves
    std::uint64_t partner_answers_ = 0;
    std::optional<SteadyTime> partner_last_answer_;
    std::optional<CmfStandbyStatus> partner_status_;
    std::uint64_t foreign_frames_ = 0;
    std::uint64_t followed_master_frames_ = 0;  // of those, sent by an adapter in followed_nics_
    std::unique_ptr<MirroredCycle> mirrored_;  // the newest mirrored cycle taken
    std::vector<master::SlaveStateEntry> slaves_;
    std::vector<std::uint8_t> master_pd_out_;
    std::vector<std::uint8_t> master_pd_in_;

    // Shared with the receive threads (the INACTIVE's answer goes into forwarded CMFs).
    mutable std::mutex pd_in_mutex_;
    std::vector<std::uint8_t> pd_in_to_send_;
    std::atomic<bool> hot_standby_{false};
    std::atomic<bool> ready_for_handoff_{false};
    std::atomic<bool> forced_standby_{false};
    std::atomic<bool> switchover_requested_{false};
    std::atomic<bool> partner_differs_{false};
    std::atomic<std::uint32_t> standby_epoch_{0};
    static constexpr std::uint64_t kNoHandoff = 0;
    std::atomic<std::uint64_t> acknowledged_handoff_{kNoHandoff};
    std::array<SteadyTime, 2> arrival_{};  // per arrival link, written by that link's receive thread
    // CMF headers of other masters (receive threads and cycle thread).
    mutable std::mutex heard_mutex_;
    std::optional<HeardActive> heard_;
    std::uint64_t headers_heard_ = 0;
    // The NIC bytes of the followed ACTIVE's MAIN [0] and RED [1] adapters, from its CMFs.
    std::array<std::optional<wire::NicBytes>, 2> followed_nics_;
    std::optional<link::Clock::time_point> partner_cycle_start_;  // estimated, of heard_'s cycle
    // For snapshot() from other threads.
    mutable std::mutex status_mutex_;
    RedundancySnapshot status_;
};

}  // namespace ecpair::redundancy
