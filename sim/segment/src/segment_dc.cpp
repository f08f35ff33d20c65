// The segment's side of the distributed clocks: the hardware every ESC gets
// (its delays and oscillator, from the options and a serial number), and
// the truth ecsim reports (DcReport): deviations from the reference clock,
// the worst since the last reset (kept by DcWatch), the spread of the latest
// SYNC0 edge and the edges missed or doubled.
//
// The spread: of the slaves that run SYNC0, take the latest nominal edge
// every one of them has passed (their last pulses' smallest system time) and
// the common times at which each produced it (its last or second-to-last
// pulse; a slave more than a pulse ahead is extrapolated from its last one);
// the spread is the latest of those times minus the earliest.

#include <fmt/format.h>

#include <algorithm>

#include "dc_watch.hpp"
#include "ecpair/sim/segment.hpp"
#include "segment_log.hpp"

namespace ecpair::sim {
namespace {

using detail::segment_log;
using detail::system_time_difference;

// splitmix64: a well-mixed value from a seed and a serial number.
std::uint64_t mix(std::uint64_t seed, std::uint64_t serial) {
    std::uint64_t z = seed + (serial + 1) * 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

struct Edge {
    SyncEdge last;
    std::optional<SyncEdge> previous;
};

std::optional<std::int64_t> spread_of(const std::vector<Edge>& edges, bool narrow) {
    if (edges.empty()) return std::nullopt;
    std::uint64_t common = edges.front().last.system_ns;
    for (const Edge& e : edges) {
        if (system_time_difference(e.last.system_ns, common, narrow) < 0) common = e.last.system_ns;
    }
    std::int64_t earliest = 0;
    std::int64_t latest = 0;
    bool first = true;
    for (const Edge& e : edges) {
        std::int64_t at = 0;
        if (system_time_difference(e.last.system_ns, common, narrow) == 0) {
            at = static_cast<std::int64_t>(e.last.at_ns);
        } else if (e.previous && system_time_difference(e.previous->system_ns, common, narrow) == 0) {
            at = static_cast<std::int64_t>(e.previous->at_ns);
        } else {
            at = static_cast<std::int64_t>(e.last.at_ns) - system_time_difference(e.last.system_ns, common, narrow);
        }
        earliest = first ? at : std::min(earliest, at);
        latest = first ? at : std::max(latest, at);
        first = false;
    }
    return latest - earliest;
}

}  // namespace

void Segment::fit_hardware(Esc& esc) {
    const PropagationOptions& p = options_.propagation;
    esc.set_propagation_delays(EscDelays::uniform(p.forwarding_ns, p.processing_ns));
    const ClockOptions& c = options_.clocks;
    const std::uint64_t serial = next_oscillator_++;
    if (c.seed == 0) {
        esc.set_oscillator(Oscillator{});
        return;
    }
    const std::int64_t span_ppb = std::int64_t{c.drift_ppm} * 1000;
    const auto drift =
        span_ppb == 0 ? 0 : static_cast<std::int64_t>(mix(c.seed, serial) % static_cast<std::uint64_t>(2 * span_ppb + 1)) - span_ppb;
    esc.set_oscillator(Oscillator{drift, mix(c.seed ^ 0x5EED5EED5EED5EEDULL, serial)});
}

void Segment::power_on_esc(std::size_t index) { escs_[index].power_on(now_ns_); }

void Segment::watch_dc(std::size_t slave, std::uint64_t time_ns) { dc_->after_call(escs_, slave, time_ns); }

Expected<void, FaultError> Segment::set_esc_delays(std::size_t position, const EscDelays& delays) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].set_propagation_delays(delays);
    refresh_digests();  // the routes' times change
    return {};
}

Expected<void, FaultError> Segment::set_oscillator(std::size_t position, const Oscillator& oscillator) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].set_oscillator(oscillator);
    dc_->rebuild(escs_);
    return {};
}

DcReport Segment::dc_report() {
    DcReport report;
    report.now_ns = now_ns_;
    dc_->rebuild(escs_);
    const auto reference = dc_->reference();
    report.reference_from_master = reference && dc_->reference_from_master();
    std::uint64_t reference_time = 0;
    bool reference_narrow = false;
    if (reference) {
        report.reference = *reference + 1;
        reference_time = escs_[*reference].dc_system_time_at(now_ns_);
        reference_narrow = escs_[*reference].description().dc == DcSupport::Dc32;
    }
    std::vector<Edge> edges;
    bool any_narrow = false;
    for (std::size_t s = 0; s < escs_.size(); ++s) {
        Esc& esc = escs_[s];
        DcSlaveReport slave;
        slave.position = s + 1;
        slave.powered = esc.powered();
        slave.truth = esc.dc_truth(now_ns_);
        report.sync0_missed += slave.truth.sync0_missed + slave.truth.sync0_doubled;
        const bool clock = slave.powered && slave.truth.support != DcSupport::None;
        const bool narrow = slave.truth.support == DcSupport::Dc32;
        if (clock && reference) {
            slave.deviation_ns =
                system_time_difference(slave.truth.system_time_ns, reference_time, narrow || reference_narrow);
        }
        if (clock && slave.truth.sync0_running) {
            ++report.synchronised;
            if (slave.deviation_ns) {
                report.max_abs_deviation_ns =
                    std::max(report.max_abs_deviation_ns, *slave.deviation_ns < 0 ? -*slave.deviation_ns : *slave.deviation_ns);
            }
            if (slave.truth.last_sync0) {
                edges.push_back(Edge{*slave.truth.last_sync0, slave.truth.previous_sync0});
                any_narrow = any_narrow || narrow;
            }
        }
        report.slaves.push_back(std::move(slave));
    }
    dc_->note(report.max_abs_deviation_ns);
    report.worst_deviation_ns = dc_->worst();
    report.sync0_spread_ns = spread_of(edges, any_narrow);
    return report;
}

void Segment::reset_dc_statistics() {
    for (auto& esc : escs_) esc.reset_dc_counters();
    const DcReport now = dc_report();
    dc_->reset_worst(now.max_abs_deviation_ns);
    segment_log().info("DC statistics reset: worst deviation and missed SYNC0 edges count from now ({} ns now)",
                       now.max_abs_deviation_ns);
}

}  // namespace ecpair::sim
