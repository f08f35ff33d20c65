// How the roles use the master's cycle (see the header for the why):
//
//   begin_cycle   INACTIVE: bring the newest mirrored cycle into the image,
//                           the master state and the slave state image, and
//                           count cycles with the partner
//                 then: ask the decider (or look at request()) and change
//                 role at this boundary if told to
//   send_frames   ACTIVE: the CMF of this cycle (after the slave frames)
//   complete      ACTIVE: the partner's answer in the returned CMF
//   foreign_frame ACTIVE: another master's frame (its CMF header is noted)
//   on_frame      receive threads: ACTIVE -> the master's rings,
//                 INACTIVE -> store-and-forward, which fills the standby
//                 status into each CMF on its first pass and feeds the mirror

#include "ecpair/redundancy/redundancy_controller.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/redundancy/redundancy_events.hpp"
#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"
#include "channel_sender.hpp"
#include "mailbox_counter_mirror.hpp"
#include "mirror.hpp"

namespace ecpair::redundancy {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("redundancy"); }

std::uint32_t as_number(RedState s) { return static_cast<std::uint32_t>(s); }

// The HEADER section of the CMF `frame` carries, if it carries it.
std::optional<CmfHeader> find_header(const wire::ConstFrameView& frame) {
    for (const auto d : frame) {
        if (!is_cmf_datagram(d)) continue;
        const auto data = d.data();
        const auto segment = CmfSegmentHeader::decode(data, d.frame_offset() + wire::kDatagramHeaderSize);
        if (!segment || segment->kind != CmfKind::Header || segment->offset != 0) continue;
        auto header = CmfHeader::decode(data.subspan(CmfSegmentHeader::kSize),
                                        d.frame_offset() + wire::kDatagramHeaderSize + CmfSegmentHeader::kSize);
        if (header) return *header;
    }
    return std::nullopt;
}

}  // namespace

std::string_view to_string(RedState state) { return state == RedState::Active ? "ACTIVE" : "INACTIVE"; }

std::string_view to_string(ForwardingPath path) { return path == ForwardingPath::Kernel ? "kernel" : "user space"; }

Expected<std::unique_ptr<RedundancyController>, std::string> RedundancyController::create(
    master::Master& master, const RedundancyOptions& options, master::EventQueue& events) {
    if (!master.has_red()) return unexpected(std::string("a redundant pair needs the RED adapter (master-master cable)"));
    CmfLayout layout;
    layout.parameters = options.parameters;
    layout.slave_count = static_cast<std::uint16_t>(master.eni().slaves.size());
    layout.shadow_inputs_size =
        options.parameters.update_slave_pd_in ? static_cast<std::uint32_t>(master.image().inputs().size()) : 0;
    auto plan = CmfPlan::make(layout);
    if (!plan) return unexpected("Cyclic Master Red Frame: " + plan.error());
    return std::unique_ptr<RedundancyController>(new RedundancyController(master, options, events, std::move(*plan)));
}

RedundancyController::RedundancyController(master::Master& master, const RedundancyOptions& options,
                                           master::EventQueue& events, CmfPlan plan)
    : master_(master),
      options_(options),
      events_(events),
      member_(master.link(master::LinkRole::Main).mac()),
      writer_(plan),
      mirror_(std::make_unique<Mirror>(plan, master.plan(), master.image().inputs().size(),
                                       master.image().outputs().size(), events, history_)),
      mailbox_counters_(std::make_unique<MailboxCounterMirror>(master.eni())),
      forwarding_(master.link(master::LinkRole::Main), master.link(master::LinkRole::Red)),
      mirrored_(std::make_unique<MirroredCycle>()) {
    const auto& p = options_.parameters;
    master_pd_out_.assign(p.master_pd_out_size, 0);
    master_pd_in_.assign(p.master_pd_in_size, 0);
    pd_in_to_send_.assign(p.master_pd_in_size, 0);
    mirrored_->master_pd_out.assign(p.master_pd_out_size, 0);
    slaves_.resize(master.eni().slaves.size());

    // The INACTIVE answers in the CMF as it forwards it, once per frame: it
    // notes the header (the partner's cycle, a hand-off it announces), then
    // fills in its master PD and its standby status.
    forwarding_.set_hook([this](master::LinkRole arrived_on, wire::FrameView& frame, bool first_pass) {
        if (channel_) channel_->process(arrived_on, frame, first_pass);
        if (!first_pass) return;
        if (const auto view = wire::ConstFrameView::parse(ConstBytes(frame.bytes()))) {
            note_header(*view, arrival_[index(arrived_on)]);
        }
        std::array<std::uint8_t, CmfStandbyStatus::kSize> status{};
        standby_status().encode(status);
        std::lock_guard lock(pd_in_mutex_);
        process_as_inactive(frame, pd_in_to_send_, status);
    });
    forwarding_.set_stored_callback([this](master::LinkRole arrived_on, ConstBytes frame, bool first_pass) {
        if (channel_) channel_->forwarded(arrived_on, frame, first_pass);
        if (!first_pass) return;
        mirror_->on_first_pass(arrived_on, frame);
        if (const auto view = wire::ConstFrameView::parse(frame)) mailbox_counters_->observe(*view);
    });

    const RedState initial = options_.start_active ? RedState::Active : RedState::Inactive;
    state_.store(initial);
    requested_.store(initial);
    master_.set_sending(initial == RedState::Active);
    if (initial == RedState::Inactive) master_.acyclic().refuse(bus::BusErrc::MasterRedStateInactive);
    master_.set_extension(this);
    status_.state = initial;
    log()->info("redundant pair member {}, starting {} (fingerprint {:016x}, CMF in {} frame(s) of {} datagram(s))",
                member_.to_string(), to_string(initial), p.fingerprint(), plan.frame_count(), plan.parts().size());
}

RedundancyController::~RedundancyController() = default;

void RedundancyController::set_acyclic_channel(AcyclicMasterRedChannel* channel) {
    channel_ = channel;
    if (channel_) channel_->role_changed(state_.load() == RedState::Active);
}

void RedundancyController::set_kernel_forwarding(std::unique_ptr<KernelForwarding> kernel) {
    kernel_ = std::move(kernel);
    if (!kernel_) return;
    kernel_->set_link_state(master::LinkRole::Main, forwarding_.link_state(master::LinkRole::Main));
    kernel_->set_link_state(master::LinkRole::Red, forwarding_.link_state(master::LinkRole::Red));
    if (state_.load() == RedState::Inactive) start_kernel_forwarding();
}

// A map write, not an attach: the cycle thread must not wait for the kernel here.
void RedundancyController::start_kernel_forwarding() {
    if (!kernel_) return;
    if (!kernel_->attached()) {
        log()->warn("the kernel store-and-forward program is not attached: user space forwards");
        return;
    }
    kernel_->set_forwarding(true);
    kernel_forwarding_.store(true, std::memory_order_release);
    publish_kernel_answer();
    log()->info("INACTIVE frames are forwarded by the kernel (user space mirrors them)");
}

void RedundancyController::publish_kernel_answer() {
    if (!kernel_forwarding_.load(std::memory_order_acquire)) return;
    std::array<std::uint8_t, CmfStandbyStatus::kSize> status{};
    standby_status().encode(status);
    std::lock_guard lock(pd_in_mutex_);
    if (auto set = kernel_->set_answer(pd_in_to_send_, status); !set) {
        events_.raise(events::kKernelAnswerNotUpdated, static_cast<std::uint32_t>(set.error()));
    }
}

void RedundancyController::observe_forwarded(master::LinkRole arrived_on, ConstBytes frame, SteadyTime at) {
    const auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    const auto source = wire::SourceMac::decode(view->ethernet().source);
    if (source.forwarded_main || source.forwarded_red) return;  // not a first pass: seen already
    const auto acknowledged = acknowledged_handoff_.load();
    note_header(*view, at);
    // The program answers a hand-off from the next CMF on.
    if (acknowledged_handoff_.load() != acknowledged) publish_kernel_answer();
    mirror_->on_first_pass(arrived_on, frame);
    mailbox_counters_->observe(*view);
    if (channel_) channel_->kernel_forwarded(arrived_on, frame, *kernel_);
}

void RedundancyController::request(RedState state) {
    if (requested_.exchange(state) != state) log()->info("{} requested", to_string(state));
}

ConstBytes RedundancyController::received_master_pd_out() const { return mirrored_->master_pd_out; }

void RedundancyController::set_master_pd_in(ConstBytes data) {
    {
        std::lock_guard lock(pd_in_mutex_);
        std::copy_n(data.begin(), std::min(data.size(), pd_in_to_send_.size()), pd_in_to_send_.begin());
    }
    publish_kernel_answer();
}

void RedundancyController::on_frame(master::LinkRole arrived_on, ConstBytes frame, link::Clock::time_point received_at) {
    if (state_.load(std::memory_order_acquire) == RedState::Active) {
        master_.on_frame(arrived_on, frame, received_at);
        if (channel_) channel_->returned(arrived_on, frame);
    } else if (kernel_forwarding_.load(std::memory_order_acquire)) {
        observe_forwarded(arrived_on, frame, received_at);
    } else {
        arrival_[index(arrived_on)] = received_at;  // for the hook, on this same thread
        forwarding_.on_frame(arrived_on, frame);
    }
}

void RedundancyController::set_link_state(master::LinkRole role, bool up) {
    master_.set_link_state(role, up);
    forwarding_.set_link_state(role, up);
    if (kernel_) kernel_->set_link_state(role, up);
}

void RedundancyController::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    events_.push(master::Event{kind, cycle_, std::chrono::system_clock::now(), a, b, c, 0});
}

bool RedundancyController::mirror_fresh() const {
    const auto last = mirror_->last_completed();
    return last && !mirror_->mismatch() && std::chrono::steady_clock::now() - *last <= options_.mirror_fresh &&
           mirrored_->cycle != 0;
}

std::optional<CmfHeader> RedundancyController::note_header(const wire::ConstFrameView& frame, SteadyTime at) {
    auto header = find_header(frame);
    if (!header || header->sender.member == member_) return std::nullopt;  // none, or one of our own coming back
    const auto& ours = writer_.plan().layout().parameters;
    const bool same = header->fingerprint == ours.fingerprint();
    {
        std::lock_guard lock(heard_mutex_);
        // The partner's cycle started about send_offset before its CMF left;
        // the earliest copy of a cycle (the direct one) tells it best.
        const auto start = at - std::chrono::nanoseconds(header->sender.send_offset_ns);
        if (heard_ && heard_->cycle == header->cycle && partner_cycle_start_) {
            partner_cycle_start_ = std::min(*partner_cycle_start_, start);
        } else {
            partner_cycle_start_ = start;
        }
        heard_ = HeardActive{header->cycle, header->master_state, header->flags, header->sender, same, at};
        ++headers_heard_;
        // The adapters of the ACTIVE this member follows: its frames after a
        // hand-off to us are told apart from another master's (foreign_frame).
        if (same && state_.load() == RedState::Inactive) {
            const auto source = wire::SourceMac::decode(frame.ethernet().source);
            followed_nics_[source.redundancy ? 1 : 0] = source.nic;
        }
    }
    // The acknowledgement follows the newest announcement: withdrawn, it is withdrawn too.
    if (same && header->flags.handoff_request && ready_for_handoff_.load()) {
        acknowledged_handoff_.store(header->sender.handoff_cycle);
    } else if (same && !header->flags.handoff_request) {
        acknowledged_handoff_.store(kNoHandoff);
    }
    return header;
}

CmfStandbyStatus RedundancyController::standby_status() const {
    CmfStandbyStatus s;
    s.hot = hot_standby_.load();
    s.forced = forced_standby_.load();
    s.partner_differs = partner_differs_.load();
    s.switchover_requested = switchover_requested_.load();
    const auto acknowledged = acknowledged_handoff_.load();
    s.handoff_acknowledged = acknowledged != kNoHandoff;
    s.handoff_cycle_low = static_cast<std::uint32_t>(acknowledged);
    s.main_link_up = forwarding_.link_state(master::LinkRole::Main);
    s.red_link_up = forwarding_.link_state(master::LinkRole::Red);
    s.member = member_;
    s.epoch = standby_epoch_.load();
    return s;
}

std::vector<std::uint8_t> RedundancyController::partner_mailbox_counters() const { return mailbox_counters_->counters(); }

std::optional<link::Clock::time_point> RedundancyController::phase_reference() const {
    if (state_.load() == RedState::Active) return std::nullopt;
    const auto period = options_.parameters.cycle_time;
    std::lock_guard lock(heard_mutex_);
    if (!partner_cycle_start_ || !heard_ || !heard_->same_fingerprint) return std::nullopt;
    // Too old to say where the partner's cycle is now (it may have stopped).
    if (link::Clock::now() - *partner_cycle_start_ > 8 * period) return std::nullopt;
    return *partner_cycle_start_ + period / kPhaseLagDivisor;
}

void RedundancyController::apply_mirror(master::ProcessImage& image) {
    if (!mirror_->take_newer(*mirrored_)) return;
    left_bus_.reset();  // another master drives the bus now: its mirror is what counts
    const auto& p = options_.parameters;
    if (p.update_slave_pd_in) {
        std::copy_n(mirrored_->inputs.begin(), std::min(mirrored_->inputs.size(), image.inputs().size()),
                    image.inputs().begin());
    }
    if (p.update_slave_pd_out) {
        std::copy_n(mirrored_->outputs.begin(), std::min(mirrored_->outputs.size(), image.outputs().size()),
                    image.outputs().begin());
    }
    master_.request_state(mirrored_->master_state);
    master_.slaves().assign(mirrored_->slaves);
}

void RedundancyController::change_role(RedState to, master::ProcessImage& image) {
    const RedState from = state_.load();
    RoleChange change{from, to, false, master_.state()};
    if (to == RedState::Active) {
        apply_mirror(image);  // the newest the partner sent, if any
        const bool from_mirror = mirror_fresh();
        // Back on the bus shortly after leaving it (a collision's backoff),
        // with nobody mirrored since: the slaves are still where this master
        // left them, and so is its image.
        const bool own = !from_mirror && left_bus_ &&
                         std::chrono::steady_clock::now() - left_bus_->at <= options_.mirror_fresh;
        change.hot = from_mirror || own;
        change.master_state = from_mirror ? mirrored_->master_state
                              : own       ? left_bus_->master_state
                                          : eni::SlaveState::Init;
        left_bus_.reset();
        if (kernel_forwarding_.exchange(false)) kernel_->set_forwarding(false);  // before the first frame goes out
        // Hot: keep the slaves where the partner had them and send the mirrored
        // outputs in this very cycle. Cold: start over from INIT.
        master_.request_state(change.master_state);
        master_.acyclic().refuse(std::nullopt);
        master_.set_sending(true);
        acknowledged_handoff_.store(kNoHandoff);
        partner_last_answer_.reset();
        partner_status_.reset();
        state_.store(RedState::Active, std::memory_order_release);
        log()->warn("now ACTIVE: {} takeover in {} ({})", change.hot ? "hot" : "cold",
                    eni::to_string(change.master_state),
                    from_mirror ? fmt::format("from the mirror of the partner's cycle {}", mirrored_->cycle)
                    : own       ? std::string("back where this master left the slaves")
                                : std::string("no fresh mirror"));
        raise(events::kRedStateChanged, as_number(from), as_number(to));
        raise(events::kTakeover, change.hot ? 1 : 0, static_cast<std::uint32_t>(change.master_state));
    } else {
        left_bus_ = LeftBus{std::chrono::steady_clock::now(), master_.state()};
        master_.set_sending(false);
        master_.acyclic().refuse(bus::BusErrc::MasterRedStateInactive);
        mirror_->reset();
        mirrored_->cycle = 0;
        followed_cycle_ = 0;
        announced_handoff_.reset();
        announced_committed_ = false;
        state_.store(RedState::Inactive, std::memory_order_release);
        start_kernel_forwarding();
        log()->warn("now INACTIVE: sending stops, store-and-forward ({}) and mirror from the partner",
                    to_string(kernel_forwarding_.load() ? ForwardingPath::Kernel : ForwardingPath::User));
        raise(events::kRedStateChanged, as_number(from), as_number(to));
    }
    if (channel_) channel_->role_changed(to == RedState::Active);
    if (on_role_change_) on_role_change_(change);
}

PairObservation RedundancyController::observe() const {
    PairObservation seen;
    seen.now = std::chrono::steady_clock::now();
    seen.cycle = cycle_;
    seen.role = state_.load();
    seen.master_state = master_.state();
    seen.main_link_up = master_.link_up(master::LinkRole::Main);
    seen.red_link_up = master_.link_up(master::LinkRole::Red);
    seen.member = member_;
    {
        std::lock_guard lock(heard_mutex_);
        seen.headers_heard = headers_heard_;
        seen.heard = heard_;
    }
    seen.cmfs_completed = mirror_->completed();
    seen.last_cmf_completed = mirror_->last_completed();
    seen.mirror_fresh = mirror_fresh();
    seen.mirrored_cycle = mirrored_->cycle;
    if (const auto acknowledged = acknowledged_handoff_.load(); acknowledged != kNoHandoff) {
        seen.acknowledged_handoff = acknowledged;
    }
    seen.partner_answers = partner_answers_;
    seen.partner_last_answer = partner_last_answer_;
    seen.partner_status = partner_status_;
    seen.foreign_frames = foreign_frames_;
    seen.followed_master_frames = followed_master_frames_;
    seen.cycles_without_return = master_.cycles_without_return();
    seen.slaves_reached = master_.slaves_reached();
    return seen;
}

void RedundancyController::apply(const RoleDecision& decision, master::ProcessImage& image) {
    epoch_ = decision.epoch;
    standby_epoch_.store(decision.epoch);
    ready_for_handoff_.store(decision.ready_for_handoff);
    if (!decision.ready_for_handoff) acknowledged_handoff_.store(kNoHandoff);
    forced_standby_.store(decision.forced_standby);
    switchover_requested_.store(decision.switchover_requested);
    if (decision.role == RedState::Active && state_.load() != RedState::Active && decision.first_cycle) {
        cycle_ = *decision.first_cycle;
        master_.follow_cycle(cycle_);  // applied before anything of this cycle is sent
    }
    if (decision.role && *decision.role != state_.load()) change_role(*decision.role, image);
    announced_handoff_ = state_.load() == RedState::Active ? decision.handoff_cycle : std::nullopt;
    announced_committed_ = announced_handoff_ && decision.handoff_committed;
}

void RedundancyController::begin_cycle(master::ProcessImage& image, std::uint64_t cycle,
                                       link::Clock::time_point cycle_start) {
    image_ = &image;
    cycle_ = cycle;
    cycle_start_ = cycle_start;
    if (state_.load() == RedState::Inactive) {
        apply_mirror(image);
        // Count with the partner: this cycle is the one after its newest mirrored one.
        if (mirrored_->cycle != 0 && mirrored_->cycle != followed_cycle_) {
            followed_cycle_ = mirrored_->cycle;
            cycle_ = mirrored_->cycle + 1;
            master_.follow_cycle(cycle_);
        }
        hot_standby_.store(mirror_fresh());
        partner_differs_.store(mirror_->mismatch().has_value());
    }
    if (decider_ != nullptr) {
        apply(decider_->decide(observe()), image);
    } else if (const RedState requested = requested_.load(); requested != state_.load()) {
        change_role(requested, image);
    }
    publish_kernel_answer();  // this cycle's standby status
    if (channel_ && kernel_forwarding_.load(std::memory_order_acquire)) channel_->prepare_answers(*kernel_);
    publish_status();
}

void RedundancyController::publish_status() {
    const bool active = state_.load() == RedState::Active;
    std::lock_guard lock(status_mutex_);
    status_.state = state_.load();
    status_.partner_seen = active ? partner_last_answer_ && std::chrono::steady_clock::now() - *partner_last_answer_ <=
                                                                options_.partner_silence
                                  : mirror_fresh();
    status_.mirrored_cycle = mirrored_->cycle;
    status_.partner_status = partner_status_;
    status_.partner_last_answer = partner_last_answer_;
    status_.last_cmf_completed = mirror_->last_completed();
    status_.epoch = epoch_;
    if (active) {
        status_.handoff_cycle = announced_handoff_;
        status_.master_pd_out.assign(master_pd_out_.begin(), master_pd_out_.end());
        status_.master_pd_in.assign(master_pd_in_.begin(), master_pd_in_.end());
    } else {
        const auto acknowledged = acknowledged_handoff_.load();
        status_.handoff_cycle = acknowledged == kNoHandoff ? std::nullopt : std::optional<std::uint64_t>(acknowledged);
        status_.master_pd_out.assign(mirrored_->master_pd_out.begin(), mirrored_->master_pd_out.end());
        std::lock_guard pd_lock(pd_in_mutex_);
        status_.master_pd_in.assign(pd_in_to_send_.begin(), pd_in_to_send_.end());
    }
}

void RedundancyController::send_frames(master::FrameSender& sender, std::uint64_t cycle) {
    if (image_ == nullptr) return;
    master_.slaves().copy_to(slaves_);
    CmfContent content;
    content.cycle = cycle;
    content.master_state = master_.state();
    content.flags.ring_broken = master_.ring_state() == master::RingState::Broken;
    content.flags.handoff_request = announced_handoff_.has_value();
    content.flags.handoff_committed = announced_committed_;
    content.sender.epoch = epoch_;
    content.sender.handoff_cycle = announced_handoff_.value_or(0);
    content.sender.slaves_reached = master_.slaves_reached().value_or(0);
    content.sender.member = member_;
    content.sender.send_offset_ns = static_cast<std::uint32_t>(std::clamp<std::int64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(link::Clock::now() - cycle_start_).count(), 0,
        std::numeric_limits<std::uint32_t>::max()));
    content.slaves = slaves_;
    if (options_.parameters.update_slave_pd_in) content.shadow_inputs = image_->inputs();
    content.master_pd_out = master_pd_out_;
    if (auto written = writer_.write(content, sender); !written) {
        const auto& error = written.error();
        raise(events::kCmfNotSent, static_cast<std::uint32_t>(error.what), static_cast<std::uint32_t>(error.expected),
              static_cast<std::uint32_t>(error.actual));
        return;
    }
    history_.record(cycle, image_->inputs(), image_->outputs(), content.master_state, false);
    if (channel_) {
        ChannelSender channel_sender(sender, kAcyclicChannelIndexBase, options_.parameters.max_acyc_frames_per_cycle);
        channel_->send_frames(channel_sender, cycle, options_.parameters.max_acyc_frames_per_cycle);
    }
}

void RedundancyController::read_partner_answer(ConstBytes frame) {
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    for (const auto d : *view) {
        if (!is_cmf_datagram(d)) continue;
        const auto segment = CmfSegmentHeader::decode(d.data(), d.frame_offset() + wire::kDatagramHeaderSize);
        // The INACTIVE filled these in on the way (WKC +1): the partner is there.
        if (!segment || d.wkc() == 0) continue;
        const auto payload = d.data().subspan(CmfSegmentHeader::kSize);
        if (segment->kind == CmfKind::MasterPdIn) {
            if (segment->offset < master_pd_in_.size()) {
                const std::size_t n = std::min(payload.size(), master_pd_in_.size() - segment->offset);
                std::copy_n(payload.begin(), n, master_pd_in_.begin() + segment->offset);
            }
        } else if (segment->kind == CmfKind::StandbyStatus && segment->offset == 0 &&
                   payload.size() >= CmfStandbyStatus::kSize) {
            partner_status_ = CmfStandbyStatus::decode(payload);
            partner_last_answer_ = std::chrono::steady_clock::now();
            ++partner_answers_;
        }
    }
}

void RedundancyController::complete(std::uint16_t index, const master::ReturnedCopy& main_copy,
                                    const master::ReturnedCopy& red_copy) {
    if (index >= kAcyclicChannelIndexBase) {
        if (channel_) channel_->complete(static_cast<std::uint16_t>(index - kAcyclicChannelIndexBase), main_copy, red_copy);
        return;
    }
    for (const auto* copy : {&main_copy, &red_copy}) {
        if (copy->path != master::CopyPath::Missing) read_partner_answer(copy->frame);
    }
}

void RedundancyController::foreign_frame(master::LinkRole, ConstBytes frame) {
    ++foreign_frames_;
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    const auto nic = wire::SourceMac::decode(view->ethernet().source).nic;
    {
        std::lock_guard lock(heard_mutex_);
        if (followed_nics_[0] == nic || followed_nics_[1] == nic) ++followed_master_frames_;
    }
    note_header(*view, std::chrono::steady_clock::now());
}

RedundancySnapshot RedundancyController::snapshot() const {
    RedundancySnapshot s;
    {
        std::lock_guard lock(status_mutex_);
        s = status_;
    }
    {
        std::lock_guard lock(heard_mutex_);
        s.heard = heard_;
    }
    s.partner_mismatch = mirror_->mismatch();
    s.forwarding = forwarding_.counters();
    if (kernel_) {
        const auto k = kernel_->counters();
        s.forwarding.forwarded_main_to_red += k.forwarded_main_to_red;
        s.forwarding.forwarded_red_to_main += k.forwarded_red_to_main;
        s.forwarding.bounced += k.bounced;
        s.forwarding.dropped_circulating += k.dropped_circulating;
        s.forwarding.dropped_non_ethercat += k.dropped_non_ethercat;
        s.forwarding.dropped_damaged += k.dropped_damaged;
    }
    s.forwarding_path = kernel_forwarding_.load() ? ForwardingPath::Kernel : ForwardingPath::User;
    return s;
}

}  // namespace ecpair::redundancy
