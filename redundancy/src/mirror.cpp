#include "mirror.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/common/log.hpp"
#include "ecpair/redundancy/redundancy_events.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::redundancy {
namespace {

// A cycle counter this far behind the newest is another ACTIVE's, not a late copy.
constexpr std::uint64_t kRestartDistance = 64;

}  // namespace

Mirror::Mirror(const CmfPlan& plan, const master::CyclicPlan& cyclic, std::size_t input_size, std::size_t output_size,
               master::EventQueue& events, ImageHistory& history)
    : links_{PerLink(plan, output_size), PerLink(plan, output_size)}, events_(events), history_(history) {
    for (const auto& frame : cyclic.frames) {
        for (const auto& d : frame.datagrams) {
            if (d.output_offset && *d.output_offset + d.length <= output_size) {
                slices_.push_back({d.command, d.address, d.length, *d.output_offset, d.states});
            }
        }
    }
    for (auto& link : links_) link.written.assign(slices_.size(), false);
    latest_.inputs.assign(input_size, 0);
    latest_.outputs.assign(output_size, 0);
    latest_.slaves.resize(plan.layout().slave_count);
    latest_.master_pd_out.assign(plan.layout().parameters.master_pd_out_size, 0);
}

void Mirror::on_first_pass(master::LinkRole arrived_on, ConstBytes frame) {
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    PerLink& link = links_[index(arrived_on)];
    if (const auto generation = generation_.load(std::memory_order_acquire); link.generation != generation) {
        // Mirroring (re)started: an output frame this link saw before belongs to no cycle to come.
        std::fill(link.written.begin(), link.written.end(), false);
        link.generation = generation;
    }
    for (const auto d : *view) {
        if (is_cmf_datagram(d)) {
            auto outcome = link.assembler.feed(d);
            if (!outcome) {
                errors_.fetch_add(1, std::memory_order_relaxed);
                if (outcome.error().code == CmfErrc::PartnerDiffers || outcome.error().code == CmfErrc::LayoutMismatch) {
                    report_mismatch(arrived_on);
                } else {
                    logger("mirror")->debug("CMF from {}: {}", master::to_string(arrived_on), outcome.error().describe());
                }
                continue;
            }
            if (*outcome == CmfAssembler::Outcome::Completed) publish(arrived_on);
            continue;
        }
        const auto slice = std::find_if(slices_.begin(), slices_.end(), [&d](const OutputSlice& s) {
            return s.command == d.command() && s.address == d.address() && s.length == d.length();
        });
        if (slice != slices_.end()) {
            std::copy(d.data().begin(), d.data().end(), link.outputs.begin() + slice->offset);
            link.written[static_cast<std::size_t>(slice - slices_.begin())] = true;
        }
    }
}

bool Mirror::wrote_every_slice(const PerLink& link, eni::SlaveState state) const {
    for (std::size_t i = 0; i < slices_.size(); ++i) {
        if (slices_[i].states.contains(state) && !link.written[i]) return false;
    }
    return true;
}

void Mirror::publish(master::LinkRole arrived_on) {
    PerLink& link = links_[index(arrived_on)];
    const CmfContent& content = link.assembler.content();
    const bool outputs_of_this_cycle = wrote_every_slice(link, content.master_state);
    std::fill(link.written.begin(), link.written.end(), false);
    const auto bit = static_cast<std::uint8_t>(1u << index(arrived_on));
    std::lock_guard lock(mutex_);
    last_completed_ = std::chrono::steady_clock::now();
    completed_.fetch_add(1, std::memory_order_relaxed);
    if (mismatch_) {
        logger("mirror")->info("partner agrees again: mirroring");
        mismatch_.reset();
    }
    if (content.cycle == latest_.cycle && latest_.copies != 0) {
        latest_.copies |= bit;
        latest_.complete = latest_.copies == 0x3 || latest_.flags.ring_broken;
        if (!latest_.outputs_known && outputs_of_this_cycle) {
            // The first copy's link missed an output frame of this cycle; this one did not.
            std::copy(link.outputs.begin(), link.outputs.end(), latest_.outputs.begin());
            latest_.outputs_known = true;
            history_.record(latest_.cycle, latest_.inputs, latest_.outputs, latest_.master_state, true);
        }
        return;
    }
    // The other copy of an older cycle, late; unless the counter jumped back
    // far: then another ACTIVE counts (the partner restarted or took over).
    if (content.cycle < latest_.cycle && latest_.cycle - content.cycle <= kRestartDistance) return;
    if (latest_.copies != 0 && !latest_.outputs_known) {
        logger("mirror")->debug("cycle {}: neither copy brought its outputs (an output frame lost on both links), "
                                "not recorded", latest_.cycle);
    }
    latest_.cycle = content.cycle;
    latest_.master_state = content.master_state;
    latest_.flags = content.flags;
    const auto inputs = content.shadow_inputs;
    std::copy_n(inputs.begin(), std::min(inputs.size(), latest_.inputs.size()), latest_.inputs.begin());
    if (outputs_of_this_cycle) std::copy(link.outputs.begin(), link.outputs.end(), latest_.outputs.begin());
    latest_.outputs_known = outputs_of_this_cycle;
    std::copy(content.slaves.begin(), content.slaves.end(), latest_.slaves.begin());
    std::copy_n(content.master_pd_out.begin(), std::min(content.master_pd_out.size(), latest_.master_pd_out.size()),
                latest_.master_pd_out.begin());
    latest_.copies = bit;
    latest_.complete = latest_.flags.ring_broken;
    if (outputs_of_this_cycle) {
        history_.record(latest_.cycle, latest_.inputs, latest_.outputs, latest_.master_state, true);
    }
}

namespace {

std::uint32_t difference_mask(const PairParameters& ours, const PairParameters& theirs) {
    std::uint32_t mask = 0;
    if (ours.eni_content_hash != theirs.eni_content_hash) mask |= kDiffersEni;
    if (ours.cycle_time != theirs.cycle_time) mask |= kDiffersCycleTime;
    if (ours.cable_redundancy != theirs.cable_redundancy) mask |= kDiffersCableRedundancy;
    if (ours.split_lrw != theirs.split_lrw) mask |= kDiffersSplitLrw;
    if (ours.master_pd_out_size != theirs.master_pd_out_size) mask |= kDiffersMasterPdOut;
    if (ours.master_pd_in_size != theirs.master_pd_in_size) mask |= kDiffersMasterPdIn;
    if (ours.update_slave_pd_in != theirs.update_slave_pd_in) mask |= kDiffersUpdateSlavePdIn;
    if (ours.update_slave_pd_out != theirs.update_slave_pd_out) mask |= kDiffersUpdateSlavePdOut;
    if (ours.max_acyc_frames_per_cycle != theirs.max_acyc_frames_per_cycle) mask |= kDiffersMaxAcycFrames;
    return mask == 0 ? kDiffersLayout : mask;
}

}  // namespace

void Mirror::report_mismatch(master::LinkRole arrived_on) {
    const auto& assembler = links_[index(arrived_on)].assembler;
    const auto& header = assembler.last_header();
    if (!header) return;
    const auto& ours = assembler.plan().layout().parameters;
    const auto differs = differences(ours, header->parameters);
    std::string text = differs.empty() ? std::string("the CMF layout (slave count or image sizes)")
                                       : fmt::format("{}", fmt::join(differs, "; "));
    std::lock_guard lock(mutex_);
    if (mismatch_ == text) return;
    mismatch_ = text;
    logger("mirror")->error("the partner differs, not mirroring it (cold standby): {}", text);
    events_.raise(events::kPartnerMismatch, difference_mask(ours, header->parameters));
}

void Mirror::reset() {
    generation_.fetch_add(1, std::memory_order_acq_rel);
    std::lock_guard lock(mutex_);
    latest_.cycle = 0;
    latest_.copies = 0;
    latest_.complete = false;
    last_completed_.reset();
}

bool Mirror::take_newer(MirroredCycle& out) const {
    std::lock_guard lock(mutex_);
    // The same cycle again once a later copy brought the outputs the first lacked.
    if (latest_.copies == 0 || (latest_.cycle == out.cycle && latest_.outputs_known == out.outputs_known)) return false;
    out.cycle = latest_.cycle;
    out.outputs_known = latest_.outputs_known;
    out.master_state = latest_.master_state;
    out.flags = latest_.flags;
    out.copies = latest_.copies;
    out.complete = latest_.complete;
    out.inputs.assign(latest_.inputs.begin(), latest_.inputs.end());
    out.outputs.assign(latest_.outputs.begin(), latest_.outputs.end());
    out.slaves.assign(latest_.slaves.begin(), latest_.slaves.end());
    out.master_pd_out.assign(latest_.master_pd_out.begin(), latest_.master_pd_out.end());
    return true;
}

std::optional<std::string> Mirror::mismatch() const {
    std::lock_guard lock(mutex_);
    return mismatch_;
}

std::optional<std::chrono::steady_clock::time_point> Mirror::last_completed() const {
    std::lock_guard lock(mutex_);
    return last_completed_;
}

}  // namespace ecpair::redundancy
