#include "dc_watch.hpp"

#include <cstdlib>

namespace ecpair::sim::detail {
namespace {

bool has_dc(const Esc& esc) { return esc.powered() && esc.description().dc != DcSupport::None; }
bool narrow(const Esc& esc) { return esc.description().dc == DcSupport::Dc32; }

std::int64_t magnitude(std::int64_t value) { return value < 0 ? -value : value; }

}  // namespace

std::int64_t system_time_difference(std::uint64_t a, std::uint64_t b, bool narrow) {
    if (narrow) return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
    return static_cast<std::int64_t>(a - b);
}

void DcWatch::rebuild(std::span<Esc> escs) {
    seen_.resize(escs.size());
    for (std::size_t s = 0; s < escs.size(); ++s) seen_[s] = escs[s].dc_counters();
    if (reference_ && (*reference_ >= escs.size() || !has_dc(escs[*reference_]))) reference_.reset();
    if (!reference_) choose_reference(escs);
}

void DcWatch::choose_reference(std::span<Esc> escs) {
    from_master_ = false;
    reference_.reset();
    for (std::size_t s = 0; s < escs.size(); ++s) {
        if (has_dc(escs[s])) {
            reference_ = s;
            return;
        }
    }
}

void DcWatch::note(std::int64_t deviation_ns) {
    const std::int64_t size = magnitude(deviation_ns);
    if (size > worst_) worst_ = size;
}

void DcWatch::measure_all(std::span<Esc> escs, std::uint64_t t, const DcClockStep* reference_step) {
    const Esc& reference = escs[*reference_];
    const std::uint64_t reference_now = reference.dc_system_time_at(t);
    for (std::size_t s = 0; s < escs.size(); ++s) {
        if (s == *reference_ || !seen_[s].sync0_running || !has_dc(escs[s])) continue;
        const bool narrower = narrow(escs[s]) || narrow(reference);
        const std::uint64_t own = escs[s].dc_system_time_at(t);
        if (reference_step != nullptr) note(system_time_difference(own, reference_step->before, narrower));
        note(system_time_difference(own, reference_now, narrower));
    }
}

void DcWatch::changed(std::span<Esc> escs, std::size_t slave, const DcCounters& counters, std::uint64_t time_ns) {
    const DcCounters before = seen_[slave];
    seen_[slave] = counters;
    if (counters.reference_reads != before.reference_reads) {
        from_master_ = true;  // the master reads its reference time here
        if (reference_ != slave) {
            reference_ = slave;
            measure_all(escs, time_ns, nullptr);
            return;
        }
    }
    if (counters.steps == before.steps || !reference_) return;
    const DcClockStep& step = escs[slave].dc_last_step();
    if (slave == *reference_) {
        measure_all(escs, step.at_ns, &step);
        return;
    }
    const Esc& reference = escs[*reference_];
    const bool narrower = narrow(escs[slave]) || narrow(reference);
    const std::uint64_t reference_then = reference.dc_system_time_at(step.at_ns);
    if (step.sync0_before) note(system_time_difference(step.before, reference_then, narrower));
    if (step.sync0_after) note(system_time_difference(step.after, reference_then, narrower));
}

}  // namespace ecpair::sim::detail
