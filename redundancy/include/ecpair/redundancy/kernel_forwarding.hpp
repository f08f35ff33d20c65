#pragma once
// The INACTIVE's store-and-forward inside the kernel: an eBPF program on tc
// ingress (tcx) of both links that makes StoreAndForward's decisions for
// every frame without waking user space (redundancy/bpf/store_and_forward.bpf.c,
// docs/ARCHITECTURE.md "The frame path at the INACTIVE").
//
// Lifetime: the program is attached through bpf_link objects that only this
// process holds (not pinned, close-on-exec). When ecpaird exits - also by
// kill -9 - the kernel closes them and the program is detached: nothing goes
// on forwarding frames for a master that is gone (a tc filter attached
// through netlink would stay until its qdisc is removed, which is why this
// needs tcx, Linux 6.6 or newer).
//
// Attached is not yet forwarding: set_forwarding(true) switches the program
// on (INACTIVE), false off (ACTIVE: every frame passes to the host as if no
// program were there). Roles change by this map write, not by attaching:
// attaching or detaching a tcx link waits for an RCU grace period (40-50 ms
// measured here), far too long for the cycle thread at a role change.
//
// What user space keeps doing: feeding the answer (set_answer, every cycle
// and when the hand-off acknowledgement changes), the TAP bridge's answers
// to polls (PreparedPollAnswers: the channel prepares them ahead) and the
// link states (the link monitor's view). The counters are read from the
// program's maps.
//
// Threads: every member may be called from any thread. set_answer and
// attach/detach are serialised by a short lock; the switch and the link
// states are single map writes; the poll answers are the program's memory,
// mapped here (PreparedPollAnswers' callers serialise their calls: the
// channel's lock); counters() reads the maps under a lock of
// its own (a status request never holds up the cycle thread's set_answer).

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/redundancy/prepared_poll_answers.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"

struct store_and_forward_bpf;

namespace ecpair::redundancy {

// The largest MASTER_PD_IN the program fills in (ECPAIR_KFWD_PD_IN_MAX).
std::size_t kernel_forwarding_max_pd_in();

// What the program did with one frame, when run through BPF_PROG_TEST_RUN.
struct KernelForwardingVerdict {
    enum class Action : std::uint8_t { Redirected, Dropped, Passed } action = Action::Passed;
    std::vector<std::uint8_t> frame;  // the frame as it left the program
};

class KernelForwarding final : public PreparedPollAnswers {
public:
    // Loads the program for these two interfaces (names, looked up now).
    // Fails naming the interface that does not exist, or why the kernel
    // refused the program (no CAP_BPF/CAP_NET_ADMIN, a kernel without BPF).
    static Expected<std::unique_ptr<KernelForwarding>, std::string> open(const std::string& main_interface,
                                                                         const std::string& red_interface,
                                                                         std::size_t master_pd_in_size);
    ~KernelForwarding() override;  // detaches
    KernelForwarding(const KernelForwarding&) = delete;
    KernelForwarding& operator=(const KernelForwarding&) = delete;

    // Attaches on tc ingress of both links (both or neither); it forwards once
    // set_forwarding(true). Fails naming the interface and the kernel's reason.
    // Blocks for a grace period: not on the cycle thread.
    Expected<void, std::string> attach();
    void detach();  // blocks likewise
    bool attached() const;

    // On: the program forwards (starts off). Any thread, does not block.
    void set_forwarding(bool on);

    void set_link_state(master::LinkRole role, bool up);
    // What the program writes into the MASTER_PD_IN and STANDBY_STATUS
    // sections of every CMF on its first pass (master_pd_in is cut to the
    // size given to open()). Fails with the errno of the map update (the
    // program keeps the answer it had).
    Expected<void, int> set_answer(ConstBytes master_pd_in, ConstBytes standby_status);

    // PreparedPollAnswers: the program's slots (ECPAIR_KFWD_BRIDGE_SLOTS).
    std::size_t slots() const override;
    std::uint64_t claimed_by(std::size_t slot) const override;
    void publish(std::size_t slot, ConstBytes data) override;
    void withdraw_all() override;

    // Sums over CPUs; send_failures stays 0 (a redirect cannot fail visibly).
    StoreAndForwardCounters counters() const;

    // Runs the program once on `frame` as if it arrived on `arrived_on`
    // (BPF_PROG_TEST_RUN: nothing is sent). The interfaces must exist in the
    // calling thread's network namespace.
    Expected<KernelForwardingVerdict, std::string> run_once(master::LinkRole arrived_on, ConstBytes frame) const;

private:
    KernelForwarding(store_and_forward_bpf* skeleton, std::array<std::string, 2> names, std::array<int, 2> ifindex,
                     std::size_t master_pd_in_size);
    void set_control(std::uint32_t key, std::uint32_t value) const;

    store_and_forward_bpf* skeleton_;
    std::array<std::string, 2> names_;
    std::array<int, 2> ifindex_;
    std::size_t master_pd_in_size_;
    mutable std::mutex mutex_;
    std::array<int, 2> links_{-1, -1};  // bpf_link fds, -1: not attached
    std::uint32_t answer_slot_ = 0;     // the complete one
    std::vector<std::uint8_t> answer_;  // struct ecpair_kfwd_answer, built here
    mutable std::mutex counters_mutex_;
    mutable std::vector<std::uint64_t> per_cpu_;  // one counter's value per possible CPU
};

}  // namespace ecpair::redundancy
