#include "operator_service.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/wire/al_status.hpp"
#include "tap_bridge_status.hpp"
#include "link_guard_status.hpp"

namespace ecpair::daemon {
namespace {

void add_variables(const master::ProcessImage& layout, master::ImageSection section, ConstBytes bytes,
                   std::uint32_t limit, google::protobuf::RepeatedPtrField<control::VariableValue>& out) {
    for (const auto& ref : layout.variables(section)) {
        if (static_cast<std::uint32_t>(out.size()) >= limit) return;
        if ((ref.bit_offset + ref.bit_size + 7) / 8 > bytes.size()) continue;
        auto* v = out.Add();
        v->set_name(ref.variable->name);
        v->set_bit_size(ref.bit_size);
        v->set_value(master::read_bits(bytes, ref.bit_offset, ref.bit_size));
    }
}

}  // namespace

control::StatusReply OperatorService::status(const control::StatusRequest& request) {
    control::StatusReply reply;
    reply.set_name(settings_.name);
    reply.set_master_state(std::string(eni::to_string(master_.state())));
    // An INACTIVE master has no target of its own: it follows the partner's state.
    const bool follows_partner = redundancy_ && redundancy_->state() == redundancy::RedState::Inactive;
    reply.set_target_state(follows_partner ? std::string("partner's")
                                           : std::string(sequencer::to_string(state_machine_.target())));
    if (const auto error = state_machine_.last_error()) reply.set_sequence_error(error->message);
    reply.set_ring_state(std::string(master::to_string(master_.ring_state())));
    reply.set_reachable_from_main(master_.reachable_from_main().value_or(0));
    reply.set_main_link_up(master_.link_up(master::LinkRole::Main));
    reply.set_red_link_up(master_.has_red() && master_.link_up(master::LinkRole::Red));
    reply.set_cycle_time_us(static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::microseconds>(master_.options().cycle_time).count()));

    const auto timing = cycle_thread_.timing();
    auto* t = reply.mutable_timing();
    t->set_cycles(timing.cycles);
    t->set_late(timing.late);
    t->set_skipped(timing.skipped);
    t->set_wake_latency_p50_us(timing.latency_percentile_us(50.0));
    t->set_wake_latency_p99_us(timing.latency_percentile_us(99.0));
    t->set_wake_latency_max_us(static_cast<double>(timing.max_wake_latency.count()) / 1000.0);
    t->set_realtime(timing.realtime);

    const auto stats = master_.stats();
    auto* c = reply.mutable_counters();
    c->set_frames_sent(stats.frames_sent);
    c->set_frames_lost(stats.frames_lost);
    c->set_late_copies(stats.late_frames);
    c->set_late_copies_on_red(stats.late_frames_on_red);
    c->set_cycles_incomplete(stats.cycles_incomplete);
    c->set_wkc_errors(stats.wkc_errors);
    c->set_foreign_frames(stats.foreign_frames);
    c->set_send_errors(stats.send_errors);

    const auto slaves = master_.slaves().snapshot();
    const auto& configured = master_.eni().slaves;
    for (std::size_t i = 0; i < configured.size(); ++i) {
        auto* s = reply.add_slaves();
        s->set_position(static_cast<std::uint32_t>(i));
        s->set_name(configured[i].info.name);
        s->set_station_address(configured[i].info.phys_addr);
        s->set_present(slaves[i].present);
        s->set_al_state(slaves[i].al_status == 0 ? std::string("?")
                                                 : wire::AlStatus{slaves[i].al_status}.to_string());
        s->set_al_status_code(slaves[i].al_status_code);
    }

    if (request.max_variables() > 0) {
        const auto snapshot = master_.snapshot();
        add_variables(master_.image(), master::ImageSection::Inputs, snapshot.inputs, request.max_variables(),
                      *reply.mutable_inputs());
        add_variables(master_.image(), master::ImageSection::Outputs, snapshot.outputs, request.max_variables(),
                      *reply.mutable_outputs());
    }
    if (redundancy_) {
        const auto r = redundancy_->snapshot();
        auto* out = reply.mutable_redundancy();
        out->set_enabled(true);
        out->set_red_state(std::string(redundancy::to_string(r.state)));
        out->set_partner_seen(r.partner_seen);
        if (r.partner_mismatch) out->set_partner_mismatch(*r.partner_mismatch);
        out->set_mirrored_cycle(r.mirrored_cycle);
        out->set_master_pd_out(std::string(r.master_pd_out.begin(), r.master_pd_out.end()));
        out->set_master_pd_in(std::string(r.master_pd_in.begin(), r.master_pd_in.end()));
        out->set_forwarded_main(r.forwarding.forwarded_red_to_main);
        out->set_forwarded_red(r.forwarding.forwarded_main_to_red);
        out->set_bounced(r.forwarding.bounced);
        out->set_dropped_circulating(r.forwarding.dropped_circulating);
        out->set_dropped_non_ethercat(r.forwarding.dropped_non_ethercat);
        out->set_dropped_damaged(r.forwarding.dropped_damaged);
        out->set_forwarding_path(std::string(redundancy::to_string(r.forwarding_path)));
        if (supervisor_) add_supervisor_status(r, *reply.mutable_supervisor());
    }
    if (tap_bridge_) fill_tap_bridge_status(*tap_bridge_, *reply.mutable_tap_bridge());
    hot_connect_.fill_summary(*reply.mutable_hot_connect());
    const auto loop = demo_.stats();
    auto* l = reply.mutable_loopback();
    l->set_cycles_checked(loop.cycles_checked);
    l->set_slave_checks(loop.slaves_checked);
    l->set_mismatches(loop.mismatches);
    fill_link_guard_status(link_guard_, *reply.mutable_link_guard());
    return reply;
}

std::optional<std::string> OperatorService::set_master_state(const control::SetMasterStateRequest& request) {
    if (redundancy_ && redundancy_->state() == redundancy::RedState::Inactive) {
        const auto pair = redundancy_->snapshot();
        return fmt::format("MasterRedStateInactive: this member is INACTIVE and must not talk to the slaves; {}",
                           pair.heard ? fmt::format("the ACTIVE partner {} drives them: ask it",
                                                    pair.heard->sender.member.to_string())
                                      : std::string("no ACTIVE partner is heard"));
    }
    std::string name = request.state();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    static const std::pair<const char*, sequencer::MasterState> kStates[] = {
        {"INIT", sequencer::MasterState::Init},
        {"PREOP", sequencer::MasterState::Preop},
        {"SAFEOP", sequencer::MasterState::Safeop},
        {"OP", sequencer::MasterState::Op}};
    for (const auto& [text, state] : kStates) {
        if (name == text) {
            state_machine_.request(state);
            return std::nullopt;
        }
    }
    return "state: '" + request.state() + "' is not one of INIT, PREOP, SAFEOP, OP";
}

namespace {

constexpr const char* kNotInPair = "this controller is not part of a redundant pair (redundancy.enabled is off)";

double age_ms(const std::optional<redundancy::SteadyTime>& at) {
    if (!at) return -1.0;
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *at).count();
}

std::string standby_kind(const std::optional<redundancy::CmfStandbyStatus>& s) {
    if (!s) return {};
    if (s->partner_differs) return "differs";
    if (s->forced) return "forced";
    return s->hot ? "hot" : "cold";
}

}  // namespace

void OperatorService::add_supervisor_status(const redundancy::RedundancySnapshot& pair,
                                            control::SupervisorStatus& out) const {
    const auto s = supervisor_->status();
    out.set_state(std::string(supervisor::to_string(s.state)));
    out.set_why(s.why);
    out.set_forced_standby(s.forced_standby);
    out.set_epoch(s.epoch);
    out.set_arbitration(std::string(arbitration::to_string(s.arbitration)));
    out.set_comm_timeout_ms(static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(s.comm_timeout).count()));
    out.set_silence_ms(std::chrono::duration<double, std::milli>(s.silence).count());
    out.set_longest_silence_ms(std::chrono::duration<double, std::milli>(s.longest_silence).count());
    out.set_last_cmf_age_ms(age_ms(pair.last_cmf_completed));
    out.set_partner_answer_age_ms(age_ms(pair.partner_last_answer));
    if (pair.state == redundancy::RedState::Active && pair.partner_status) {
        out.set_partner(pair.partner_status->member.to_string());
    } else if (pair.heard) {
        out.set_partner(pair.heard->sender.member.to_string());
    }
    out.set_partner_standby(standby_kind(pair.partner_status));
    out.set_handoff_cycle(s.handoff_cycle.value_or(0));
    if (s.no_active) out.set_no_active(std::string(supervisor::to_string(*s.no_active)));
    out.set_takeovers(s.counters.takeovers);
    out.set_comm_timeouts(s.counters.comm_timeouts);
    out.set_collisions(s.counters.collisions);
    out.set_backoffs_won(s.counters.backoffs_won);
    out.set_backoffs_lost(s.counters.backoffs_lost);
    out.set_handoffs(s.counters.handoffs);
    out.set_handoffs_cancelled(s.counters.handoffs_cancelled);
    out.set_partner_lost(s.counters.partner_lost);
}

std::optional<std::string> OperatorService::set_red_state(const control::SetRedStateRequest& request) {
    if (!supervisor_) return kNotInPair;
    std::string name = request.state();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    if (name == "ACTIVE") {
        if (supervisor_->status().forced_standby) return "this member is forced to standby: release it first (unforce-standby)";
        supervisor_->request_role(redundancy::RedState::Active);
    } else if (name == "INACTIVE") {
        supervisor_->request_role(redundancy::RedState::Inactive);
    } else {
        return "state: '" + request.state() + "' is not ACTIVE or INACTIVE";
    }
    return std::nullopt;
}

std::optional<std::string> OperatorService::switchover(const control::SwitchoverRequest&) {
    if (!supervisor_) return kNotInPair;
    if (auto started = supervisor_->switchover(); !started) return started.error();
    return std::nullopt;
}

std::optional<std::string> OperatorService::force_standby(const control::ForceStandbyRequest& request) {
    if (!supervisor_) return kNotInPair;
    supervisor_->force_standby(request.forced());
    return std::nullopt;
}

control::ImageHistoryReply OperatorService::image_history(const control::ImageHistoryRequest& request) {
    control::ImageHistoryReply reply;
    if (!redundancy_) return reply;
    const auto records = redundancy_->history().snapshot();
    const std::size_t first =
        request.max_entries() > 0 && records.size() > request.max_entries() ? records.size() - request.max_entries() : 0;
    for (std::size_t i = first; i < records.size(); ++i) {
        auto* e = reply.add_entries();
        e->set_cycle(records[i].cycle);
        e->set_inputs_crc(records[i].inputs_crc);
        e->set_outputs_crc(records[i].outputs_crc);
        e->set_master_state(std::string(eni::to_string(records[i].master_state)));
        e->set_mirrored(records[i].mirrored);
    }
    return reply;
}

control::EventMessage to_message(const master::EventReport& report, const master::EventDescriber& describer) {
    control::EventMessage m;
    m.set_cycle(report.event.cycle);
    m.set_kind(std::string(report.event.kind.name()));
    m.set_text(describer.describe(report));
    m.set_unix_time_ms(
        std::chrono::duration_cast<std::chrono::milliseconds>(report.event.time.time_since_epoch()).count());
    m.set_repeat(std::string(master::to_string(report.repetition)));
    m.set_count(report.count);
    m.set_total(report.total);
    m.set_first_cycle(report.first_cycle);
    m.set_last_cycle(report.last_cycle);
    return m;
}

}  // namespace ecpair::daemon
