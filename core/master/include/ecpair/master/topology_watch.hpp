#pragma once
// Notices in the cycle that the bus changed under the cyclic frames
// (hot-connect.md §3): the AL-status BRD (0x0130) counts the slaves that
// answer, so a change of its working counter from one cycle to the next is a
// slave that came or went; without such a BRD, a change in the pattern of
// WKC deviations (which datagrams, by how much) is taken instead. And a
// slave whose DL status changed (a link came or went at one of its ports:
// a cable re-plugged elsewhere changes no count) raises its DL status event,
// which Hot-Connect has the slaves pass on in the IRQ field of every frame
// (0x0200 bit 2, cleared when its DL status is read).
//
// Once armed (by Hot-Connect, when the slaves are where the master wants
// them), such a change starts a topology change: the cycle reports it and
// calls the listener, and from then on WKC deviations are the topology
// change's, not cyclic WKC errors, until Hot-Connect has put the corrected
// expected WKCs in place and calls settle(). A bus that stays wrong after
// that (a mandatory slave gone) shows cyclic WKC errors again.
//
// after_cycle() runs on the cycle thread and allocates nothing; arm(),
// settle() and the queries are for any thread.

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "ecpair/master/cyclic_exchange.hpp"
#include "ecpair/master/cyclic_plan.hpp"

namespace ecpair::master {

inline constexpr std::uint16_t kDlStatusEvent = 0x0004;  // ECAT event request / mask bit 2

struct TopologyObservation {
    bool attributed = false;    // this cycle's WKC deviations belong to a topology change
    bool detected_now = false;  // a topology change starts in this cycle
    std::optional<std::uint16_t> slaves_before;
    std::optional<std::uint16_t> slaves_now;
};

class TopologyWatch {
public:
    explicit TopologyWatch(const CyclicPlan& plan);

    // ---- any thread
    // `on_change` is called on the cycle thread when a change starts; it must not block.
    void arm(std::function<void()> on_change);
    void disarm();
    bool armed() const { return armed_.load(); }
    // The change is dealt with: from the first cycle checked with the
    // expected WKCs set before this call, deviations are errors again.
    void settle() { settle_requested_.store(true); }
    // A change found elsewhere (a periodic count, an operator): deviations are its from now on.
    void begin_change() {
        settle_requested_.store(false);
        changing_.store(true);
    }
    bool changing() const { return changing_.load(); }
    std::uint64_t changes() const { return changes_.load(); }
    // The slave count the AL-status BRD showed last (nullopt: the plan has none, or none came back yet).
    std::optional<std::uint16_t> slaves_counted() const;

    // ---- cycle thread
    // `expectations_pending`: new expected WKCs are waiting for the cycle boundary
    // (this cycle was still checked with the old ones).
    TopologyObservation after_cycle(const CyclicExchange& exchange, std::span<const WkcMismatch> mismatches,
                                    bool expectations_pending = false);

private:
    std::vector<std::size_t> al_status_counters_;  // flat indices of the AL-status BRDs

    // Cycle thread.
    std::optional<std::uint16_t> last_count_;
    std::uint64_t last_signature_ = 0;

    std::atomic<bool> armed_{false};
    std::atomic<bool> changing_{false};
    std::atomic<bool> settle_requested_{false};
    std::atomic<bool> rebaseline_{false};  // arm(): the next count is the new reference, not a change
    std::atomic<std::uint64_t> changes_{0};
    std::atomic<std::int32_t> counted_{-1};
    mutable std::mutex listener_mutex_;  // the cycle only try_locks it
    std::function<void()> on_change_;
};

}  // namespace ecpair::master
