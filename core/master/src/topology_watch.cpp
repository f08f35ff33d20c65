#include "ecpair/master/topology_watch.hpp"

#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::master {
namespace {

// FNV-1a over which datagrams deviate and what they got.
std::uint64_t signature_of(std::span<const WkcMismatch> mismatches) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    auto mix = [&h](std::uint64_t v) {
        for (int i = 0; i < 8; ++i) {
            h ^= (v >> (8 * i)) & 0xff;
            h *= 0x100000001b3ULL;
        }
    };
    for (const auto& m : mismatches) {
        mix(reinterpret_cast<std::uintptr_t>(m.datagram));
        mix(m.received);
    }
    return h;
}

}  // namespace

TopologyWatch::TopologyWatch(const CyclicPlan& plan) {
    std::size_t flat = 0;
    for (const auto& frame : plan.frames) {
        for (const auto& d : frame.datagrams) {
            const auto ado = static_cast<std::uint16_t>(d.address >> 16);
            if (d.command == wire::Command::Brd && ado == wire::reg::kAlStatus) al_status_counters_.push_back(flat);
            ++flat;
        }
    }
}

void TopologyWatch::arm(std::function<void()> on_change) {
    {
        std::lock_guard lock(listener_mutex_);
        on_change_ = std::move(on_change);
    }
    // Counts seen before (an INACTIVE master sees none) are no reference for what comes.
    rebaseline_.store(true);
    armed_.store(true);
}

void TopologyWatch::disarm() {
    armed_.store(false);
    changing_.store(false);
    settle_requested_.store(false);
}

std::optional<std::uint16_t> TopologyWatch::slaves_counted() const {
    const auto c = counted_.load();
    return c < 0 ? std::nullopt : std::optional<std::uint16_t>(static_cast<std::uint16_t>(c));
}

TopologyObservation TopologyWatch::after_cycle(const CyclicExchange& exchange, std::span<const WkcMismatch> mismatches,
                                               bool expectations_pending) {
    TopologyObservation o;
    if (settle_requested_.load() && !expectations_pending) {
        settle_requested_.store(false);
        changing_.store(false);
    }
    std::optional<std::uint16_t> count;
    if (!al_status_counters_.empty()) count = exchange.last_wkc(al_status_counters_.front());
    const std::uint64_t signature = signature_of(mismatches);

    bool changed = false;
    if (rebaseline_.exchange(false)) {
        last_count_.reset();
        last_signature_ = signature;
    }
    if (count) {
        changed = last_count_.has_value() && *count != *last_count_;
        o.slaves_before = last_count_;
        o.slaves_now = count;
        last_count_ = count;
        counted_.store(*count);
    } else {
        changed = signature != last_signature_;
    }
    last_signature_ = signature;
    changed = changed || (exchange.irq() & kDlStatusEvent) != 0;

    if (!armed_.load()) return o;
    if (changed && !changing_.load()) {
        changing_.store(true);
        changes_.fetch_add(1);
        o.detected_now = true;
        // The listener only wakes a worker; should arm() be replacing it right now, the worker's
        // periodic check finds the change a little later instead.
        std::unique_lock lock(listener_mutex_, std::try_to_lock);
        if (lock.owns_lock() && on_change_) on_change_();
    }
    o.attributed = changing_.load() && !mismatches.empty();
    return o;
}

}  // namespace ecpair::master
