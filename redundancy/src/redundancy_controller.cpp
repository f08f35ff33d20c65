// How the roles use the master's cycle (see the header for the why):
//
//   begin_cycle   role change requested? -> change_role() at this boundary
//                 INACTIVE: bring the newest mirrored cycle into the image,
//                           the master state and the slave state image
//                 ACTIVE:   notice a partner that stopped answering
//   send_frames   ACTIVE: the CMF of this cycle (after the slave frames)
//   complete      ACTIVE: the partner's answer in the returned CMF
//   on_frame      receive threads: ACTIVE -> the master's rings,
//                 INACTIVE -> store-and-forward (which also feeds the mirror)

#include "ecpair/redundancy/redundancy_controller.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"
#include "ecpair/wire/frame.hpp"
#include "channel_sender.hpp"
#include "mirror.hpp"

namespace ecpair::redundancy {
namespace {

std::shared_ptr<spdlog::logger> log() { return logger("redundancy"); }

std::uint32_t as_number(RedState s) { return static_cast<std::uint32_t>(s); }

}  // namespace

std::string_view to_string(RedState state) { return state == RedState::Active ? "ACTIVE" : "INACTIVE"; }

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
      writer_(plan),
      mirror_(std::make_unique<Mirror>(plan, master.plan(), master.image().inputs().size(),
                                       master.image().outputs().size(), events, history_)),
      forwarding_(master.link(master::LinkRole::Main), master.link(master::LinkRole::Red)),
      mirrored_(std::make_unique<MirroredCycle>()) {
    const auto& p = options_.parameters;
    master_pd_out_.assign(p.master_pd_out_size, 0);
    master_pd_in_.assign(p.master_pd_in_size, 0);
    pd_in_to_send_.assign(p.master_pd_in_size, 0);
    mirrored_->master_pd_out.assign(p.master_pd_out_size, 0);
    slaves_.resize(master.eni().slaves.size());

    // The INACTIVE answers in the CMF as it forwards it, once per frame.
    forwarding_.set_hook([this](master::LinkRole arrived_on, wire::FrameView& frame, bool first_pass) {
        if (channel_) channel_->process(arrived_on, frame, first_pass);
        if (!first_pass) return;
        std::lock_guard lock(pd_in_mutex_);
        process_as_inactive(frame, pd_in_to_send_);
    });
    forwarding_.set_stored_callback([this](master::LinkRole arrived_on, ConstBytes frame, bool first_pass) {
        if (first_pass) mirror_->on_first_pass(arrived_on, frame);
        if (channel_) channel_->forwarded(arrived_on, frame, first_pass);
    });

    const RedState initial = options_.start_active ? RedState::Active : RedState::Inactive;
    state_.store(initial);
    requested_.store(initial);
    master_.set_sending(initial == RedState::Active);
    if (initial == RedState::Inactive) master_.acyclic().refuse(bus::BusErrc::MasterRedStateInactive);
    master_.set_extension(this);
    status_.state = initial;
    log()->info("redundant pair member, starting {} (fingerprint {:016x}, CMF in {} frame(s) of {} datagram(s))",
                to_string(initial), p.fingerprint(), plan.frame_count(), plan.parts().size());
}

RedundancyController::~RedundancyController() = default;

void RedundancyController::set_acyclic_channel(AcyclicMasterRedChannel* channel) {
    channel_ = channel;
    if (channel_) channel_->role_changed(state_.load() == RedState::Active);
}

void RedundancyController::request(RedState state) {
    if (requested_.exchange(state) != state) log()->info("{} requested", to_string(state));
}

ConstBytes RedundancyController::received_master_pd_out() const { return mirrored_->master_pd_out; }

void RedundancyController::set_master_pd_in(ConstBytes data) {
    std::lock_guard lock(pd_in_mutex_);
    std::copy_n(data.begin(), std::min(data.size(), pd_in_to_send_.size()), pd_in_to_send_.begin());
}

void RedundancyController::on_frame(master::LinkRole arrived_on, ConstBytes frame, link::Clock::time_point received_at) {
    if (state_.load(std::memory_order_acquire) == RedState::Active) {
        master_.on_frame(arrived_on, frame, received_at);
        if (channel_) channel_->returned(arrived_on, frame);
    } else {
        forwarding_.on_frame(arrived_on, frame);
    }
}

void RedundancyController::set_link_state(master::LinkRole role, bool up) {
    master_.set_link_state(role, up);
    forwarding_.set_link_state(role, up);
}

void RedundancyController::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b) {
    events_.push(master::Event{kind, cycle_, std::chrono::system_clock::now(), a, b, 0, 0});
}

bool RedundancyController::mirror_fresh() const {
    const auto last = mirror_->last_completed();
    return last && !mirror_->mismatch() && std::chrono::steady_clock::now() - *last <= options_.mirror_fresh &&
           mirrored_->cycle != 0;
}

void RedundancyController::apply_mirror(master::ProcessImage& image) {
    if (!mirror_->take_newer(*mirrored_)) return;
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
        change.hot = mirror_fresh();
        change.master_state = change.hot ? mirrored_->master_state : eni::SlaveState::Init;
        // Hot: keep the slaves where the partner had them and send the mirrored
        // outputs in this very cycle. Cold: start over from INIT.
        master_.request_state(change.master_state);
        master_.acyclic().refuse(std::nullopt);
        master_.set_sending(true);
        partner_seen_ = false;
        partner_last_seen_ = std::chrono::steady_clock::now();
        state_.store(RedState::Active, std::memory_order_release);
        log()->warn("now ACTIVE: {} takeover in {} (mirrored cycle {})", change.hot ? "hot" : "cold",
                    eni::to_string(change.master_state), mirrored_->cycle);
        raise(master::EventKind::RedStateChanged, as_number(from), as_number(to));
        raise(master::EventKind::Takeover, change.hot ? 1 : 0, static_cast<std::uint32_t>(change.master_state));
    } else {
        master_.set_sending(false);
        master_.acyclic().refuse(bus::BusErrc::MasterRedStateInactive);
        mirror_->reset();
        mirrored_->cycle = 0;
        state_.store(RedState::Inactive, std::memory_order_release);
        log()->warn("now INACTIVE: sending stops, store-and-forward and mirror from the partner");
        raise(master::EventKind::RedStateChanged, as_number(from), as_number(to));
    }
    if (channel_) channel_->role_changed(to == RedState::Active);
    if (on_role_change_) on_role_change_(change);
}

void RedundancyController::begin_cycle(master::ProcessImage& image, std::uint64_t cycle) {
    image_ = &image;
    cycle_ = cycle;
    const RedState requested = requested_.load();
    if (requested != state_.load()) change_role(requested, image);

    const bool active = state_.load() == RedState::Active;
    if (!active) {
        apply_mirror(image);
    } else if (partner_seen_ &&
               std::chrono::steady_clock::now() - partner_last_seen_ > options_.partner_silence) {
        partner_seen_ = false;
        log()->warn("the partner stopped answering in the CMF");
        raise(master::EventKind::PartnerLost);
    }

    std::lock_guard lock(status_mutex_);
    status_.state = state_.load();
    status_.partner_seen = active ? partner_seen_ : mirror_fresh();
    status_.mirrored_cycle = mirrored_->cycle;
    if (active) {
        status_.master_pd_out.assign(master_pd_out_.begin(), master_pd_out_.end());
        status_.master_pd_in.assign(master_pd_in_.begin(), master_pd_in_.end());
    } else {
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
    content.slaves = slaves_;
    if (options_.parameters.update_slave_pd_in) content.shadow_inputs = image_->inputs();
    content.master_pd_out = master_pd_out_;
    if (auto written = writer_.write(content, sender); !written) {
        log()->error("CMF not sent: {}", written.error().describe());
        return;
    }
    history_.record(cycle, image_->inputs(), image_->outputs(), content.master_state);
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
        if (!segment || segment->kind != CmfKind::MasterPdIn || d.wkc() == 0) continue;
        // The INACTIVE filled it in on the way: the partner is there.
        const auto payload = d.data().subspan(CmfSegmentHeader::kSize);
        if (segment->offset < master_pd_in_.size()) {
            const std::size_t n = std::min(payload.size(), master_pd_in_.size() - segment->offset);
            std::copy_n(payload.begin(), n, master_pd_in_.begin() + segment->offset);
        }
        partner_last_seen_ = std::chrono::steady_clock::now();
        if (!partner_seen_) {
            partner_seen_ = true;
            log()->info("the partner answers in the CMF");
            raise(master::EventKind::PartnerFound);
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

RedundancySnapshot RedundancyController::snapshot() const {
    RedundancySnapshot s;
    {
        std::lock_guard lock(status_mutex_);
        s = status_;
    }
    s.partner_mismatch = mirror_->mismatch();
    s.forwarding = forwarding_.counters();
    return s;
}

}  // namespace ecpair::redundancy
