// One cycle, in the order design.md §4 gives for the ACTIVE:
//   1. accept the frames the receive threads queued since the last cycle,
//   2. complete the frames sent in the last cycle: merge the MAIN and RED
//      copies, move inputs into the process image, check WKCs, complete acyclic
//      requests, watch the ring (line break / repair),
//   3. let the extension (redundancy) act at the cycle boundary: change role,
//      bring in a mirrored image while passive,
//   4. apply state and sending requests made since,
//   5. run the application's hook on the image,
//   6. when sending: the cyclic frames of the current state, the extension's
//      frames and up to max_acyclic_frames_per_cycle acyclic frames.
// A frame that has not come back when the next cycle starts is lost.
// Every copy sent in a cycle is queued per link and the links' batches leave
// at the end of step 6, one send_batch each (cycle_batches.hpp).

#include "ecpair/master/master.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/master/link_drain.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/source_mac.hpp"
#include "cycle_batches.hpp"

namespace ecpair::master {
namespace {

constexpr std::uint32_t kNoCount = 0xFFFF;  // TopologyChangeDetected: not known
// Copies queued per link before they leave together. A cycle of 512 slaves
// with 76 + 76 bytes each sends about 60 slave frames and 30 CMF frames; a
// busier cycle sends a full batch early and goes on.
constexpr std::size_t kCopiesPerBatch = 128;
// Frames read from one link per cycle at most (receive_in_cycle): what is
// left waits for the next cycle, so a flood cannot hold the cycle thread.
constexpr std::size_t kMaxReceivedPerCycle = 1024;

}  // namespace

std::string_view to_string(RingState state) {
    switch (state) {
        case RingState::Unknown: return "unknown";
        case RingState::Closed: return "closed";
        case RingState::Broken: return "broken";
    }
    return "?";
}

// Lets the extension send frames through the master's tracker and links.
class Master::Sender final : public FrameSender {
public:
    explicit Sender(Master& master) : master_(master) {}
    Bytes buffer() override { return master_.tx_; }
    wire::EthernetHeader ethernet() const override {
        wire::EthernetHeader h;
        h.destination = wire::MacAddress::broadcast();
        return h;
    }
    void send(std::uint16_t index, Bytes frame) override { master_.send_copies(FrameKind::MasterRed, index, frame); }

private:
    Master& master_;
};

Expected<std::unique_ptr<Master>, std::string> Master::create(std::shared_ptr<const eni::EniConfig> eni,
                                                              const MasterOptions& options, link::Link& main,
                                                              link::Link* red, EventQueue& events) {
    if (options.cable_redundancy && red == nullptr) {
        return unexpected(std::string("cable redundancy needs a RED link"));
    }
    if (red != nullptr && wire::NicBytes::of(main.mac()) == wire::NicBytes::of(red->mac())) {
        return unexpected(fmt::format("MAIN {} and RED {} have the same NIC bytes ({}): every link needs a unique MAC",
                                      main.name(), red->name(), main.mac().to_string()));
    }
    auto plan = CyclicPlan::build(*eni, PlanOptions{options.cable_redundancy, options.split_lrw});
    if (!plan) return unexpected(plan.error().message);
    const auto& layout = eni->process_image;
    const std::size_t inputs = std::max(plan->input_image_size, layout ? ProcessImage::bytes_needed(layout->inputs) : 0);
    const std::size_t outputs =
        std::max(plan->output_image_size, layout ? ProcessImage::bytes_needed(layout->outputs) : 0);
    if (inputs > ProcessImage::kMaxBytes || outputs > ProcessImage::kMaxBytes) {
        return unexpected(fmt::format("{}: the process image needs {} input and {} output bytes, more than the {} "
                                      "bytes ecpair accepts",
                                      eni->source_path, inputs, outputs, ProcessImage::kMaxBytes));
    }
    return std::unique_ptr<Master>(new Master(std::move(eni), options, main, red, events, std::move(*plan)));
}

Master::Master(std::shared_ptr<const eni::EniConfig> eni, const MasterOptions& options, link::Link& main,
               link::Link* red, EventQueue& events, CyclicPlan plan)
    : eni_(std::move(eni)),
      options_(options),
      main_(main),
      red_(red),
      events_(events),
      exchange_(std::move(plan)),
      image_(exchange_.plan().input_image_size, exchange_.plan().output_image_size, eni_->process_image),
      tracker_(wire::NicBytes::of(main.mac()), red ? wire::NicBytes::of(red->mac()) : wire::NicBytes{}),
      acyclic_(options.max_acyclic_frames_per_cycle),
      slaves_(eni_->slaves.size()),
      topology_watch_(exchange_.plan()),
      tx_batches_(std::make_unique<detail::CycleBatches>(kCopiesPerBatch)) {
    // Events raised by the workers (state machine, monitors) carry this master's cycle.
    events_.attach_cycle_counter(&cycle_counter_);
    snapshot_.inputs.assign(image_.inputs().size(), 0);
    snapshot_.outputs.assign(image_.outputs().size(), 0);
    in_flight_.reserve(256);
    constexpr auto kAcyclicWait = std::chrono::milliseconds(10);
    acyclic_patience_ = std::max<std::uint64_t>(2, static_cast<std::uint64_t>(kAcyclicWait / options.cycle_time));
    sent_this_cycle_.reserve(256);
    mismatches_.reserve(64);
    link_up_[0].store(main.link_up());
    link_up_[1].store(red != nullptr && red->link_up());
    logger("master")->info("master on {}{}: {} cyclic frame(s), {} datagram(s), {} ({} in / {} out bytes)",
                           main.name(), red ? fmt::format(" + {}", red->name()) : std::string(),
                           exchange_.frame_count(), exchange_.plan().datagram_count(),
                           to_string(exchange_.plan().convention), image_.inputs().size(), image_.outputs().size());
}

Master::~Master() {
    events_.attach_cycle_counter(nullptr);
    acyclic_.refuse(bus::BusErrc::Cancelled);
    acyclic_.fail_in_flight(bus::BusErrc::Cancelled);
}

bool Master::use_red() const { return options_.cable_redundancy && red_ != nullptr; }

void Master::set_link_state(LinkRole role, bool up) {
    if (link_up_[static_cast<std::size_t>(role)].exchange(up) != up) {
        raise(up ? events::kLinkUp : events::kLinkDown, static_cast<std::uint32_t>(role));
    }
}

void Master::on_frame(LinkRole arrived_on, ConstBytes frame, link::Clock::time_point received_at) {
    rx_rings_[static_cast<std::size_t>(arrived_on)].push(frame, received_at);
}

// Called from the cycle thread and from the daemon's link watcher: the cycle
// number comes from the atomic counter, not from the cycle thread's own copy.
void Master::raise(EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    events_.push(Event{kind, cycle_counter_.load(), std::chrono::system_clock::now(), a, b, c, d});
}

MasterStats Master::stats() const {
    MasterStats s;
    s.cycles = stats_.cycles.load();
    s.frames_sent = stats_.frames_sent.load();
    s.frames_lost = stats_.frames_lost.load();
    s.cycles_incomplete = stats_.cycles_incomplete.load();
    s.wkc_errors = stats_.wkc_errors.load();
    s.wkc_topology_deviations = stats_.wkc_topology_deviations.load();
    s.foreign_frames = stats_.foreign_frames.load();
    s.late_frames = stats_.late_frames.load();
    s.late_frames_on_red = stats_.late_frames_on_red.load();
    s.send_errors = stats_.send_errors.load();
    s.rx_dropped = rx_rings_[0].dropped() + rx_rings_[1].dropped();
    return s;
}

void Master::run_cycle(link::Clock::time_point now) {
    cycle_counter_.store(++cycle_);
    accept_returned_frames();
    complete_previous_cycle(now);
    if (extension_) extension_->begin_cycle(image_, cycle_, now);
    apply_followed_cycle();
    apply_requests();
    if (hook_) hook_(image_, CycleInfo{cycle_, state_.load(), inputs_valid_, sending_.load()});
    if (sending_.load()) send_frames(now);
    publish_snapshot();
    in_flight_.swap(sent_this_cycle_);
    sent_this_cycle_.clear();
    stats_.cycles.fetch_add(1, std::memory_order_relaxed);
}

// A standby master takes the partner's cycle number for this cycle, before
// anything of the cycle is sent or reported.
void Master::apply_followed_cycle() {
    const auto follow = cycle_to_follow_.exchange(0);
    if (follow == 0 || sending_.load()) return;
    // Frames still awaited (acyclic ones, carried over) were sent under the old count: give them up.
    for (const InFlight& f : sent_this_cycle_) {
        tracker_.close(f.id);
        if (f.kind == FrameKind::Acyclic) acyclic_.complete(f.index, nullptr, link::Clock::now());
    }
    sent_this_cycle_.clear();
    cycle_ = follow;
    cycle_counter_.store(cycle_);
}

void Master::publish_snapshot() {
    // Readers copy out under this lock; rather than wait for one, the cycle
    // skips publishing this time (the next cycle publishes again).
    std::unique_lock lock(snapshot_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    snapshot_.cycle = cycle_;
    snapshot_.state = state_.load();
    snapshot_.inputs_valid = inputs_valid_;
    std::copy(image_.inputs().begin(), image_.inputs().end(), snapshot_.inputs.begin());
    std::copy(image_.outputs().begin(), image_.outputs().end(), snapshot_.outputs.begin());
}

ImageSnapshot Master::snapshot() const {
    std::lock_guard lock(snapshot_mutex_);
    return snapshot_;
}

void Master::accept_returned_frames() {
    if (options_.receive_in_cycle) {
        receive_from_links();
        return;
    }
    for (const LinkRole role : {LinkRole::Main, LinkRole::Red}) {
        rx_rings_[static_cast<std::size_t>(role)].drain([&](const RingFrame& frame) { accept_copy(role, frame.frame()); });
    }
}

// receive_in_cycle: what waits on each link is read now, in one pass per link
// (libpcap's capture ring hands over the waiting frames without a system call each).
void Master::receive_from_links() {
    for (const LinkRole role : {LinkRole::Main, LinkRole::Red}) {
        if (role == LinkRole::Red && red_ == nullptr) continue;
        drain_link(link(role), rx_, kMaxReceivedPerCycle,
                   [this, role](ConstBytes frame, link::Clock::time_point) { accept_copy(role, frame); });
    }
}

void Master::accept_copy(LinkRole role, ConstBytes frame) {
    const auto outcome = tracker_.accept(role, frame);
    if (outcome == AcceptOutcome::Stale) {
        stats_.late_frames.fetch_add(1, std::memory_order_relaxed);
        if (role == LinkRole::Red) stats_.late_frames_on_red.fetch_add(1, std::memory_order_relaxed);
    }
    if (outcome != AcceptOutcome::Foreign) return;
    stats_.foreign_frames.fetch_add(1, std::memory_order_relaxed);
    if (extension_) extension_->foreign_frame(role, frame);
    // One event per cycle is enough to say "another master is on this bus".
    if (foreign_reported_cycle_ != cycle_) {
        foreign_reported_cycle_ = cycle_;
        raise(events::kFrameResponseError, static_cast<std::uint32_t>(FrameResponseReason::ForeignSourceMac),
              static_cast<std::uint32_t>(role));
    }
}

void Master::complete_previous_cycle(link::Clock::time_point now) {
    bool any_cyclic = false;
    bool any_returned = false;
    bool all_complete = true;
    bool ring_closed = false;
    bool ring_broken = false;
    bool lost_reported = false;
    std::optional<std::uint16_t> reachable;
    std::uint64_t wkc_errors = 0;
    std::optional<std::uint16_t> answered_brd;  // the largest WKC of a returned cyclic BRD
    const bool sent_any = !in_flight_.empty();
    mismatches_.clear();

    for (const InFlight& f : in_flight_) {
        const ReturnedCopy main_copy = tracker_.copy(f.id, LinkRole::Main);
        const ReturnedCopy red_copy = f.sent_red ? tracker_.copy(f.id, LinkRole::Red) : ReturnedCopy{};
        if (f.kind == FrameKind::Cyclic) any_cyclic = true;
        if (f.kind == FrameKind::MasterRed) {
            tracker_.close(f.id);
            if (extension_) extension_->complete(f.index, main_copy, red_copy);
            continue;
        }
        auto merged = main_copy.path == CopyPath::Missing && red_copy.path == CopyPath::Missing
                          ? Expected<MergeResult, MergeError>(unexpected(MergeError{"lost"}))
                          : merge_copies(tracker_.sent_bytes(f.id), main_copy, red_copy, merged_);
        std::optional<wire::ConstFrameView> view;
        if (merged) {
            auto parsed = wire::ConstFrameView::parse(ConstBytes(merged_.data(), merged->size));
            if (parsed) view = *parsed;
        }
        const bool complete = view.has_value() && is_complete(f, main_copy, red_copy, *merged, *view);
        if (!complete && f.kind == FrameKind::Acyclic && cycle_ - f.cycle < acyclic_patience_) {
            // An acyclic frame may come back a little late. Sending it again
            // could repeat what a slave already did (reading a mailbox empties
            // it), so it is awaited for a while before it counts as lost.
            sent_this_cycle_.push_back(f);
            continue;
        }
        tracker_.close(f.id);
        if (merged) {
            any_returned = true;
            ring_closed = ring_closed || merged->ring_closed;
            ring_broken = ring_broken || merged->ring_broken;
            // What answered the AL-status BRD is what this master reaches, complete frame or not
            // (one half of a ring broken twice never meets the ENI's WKCs).
            if (f.kind == FrameKind::Cyclic && view) {
                for (const auto d : *view) {
                    if (d.command() == wire::Command::Brd) answered_brd = std::max(answered_brd.value_or(0), d.wkc());
                }
            }
        }
        if (main_copy.path == CopyPath::BouncedMain) {
            // A BRD's WKC in a MAIN copy that bounced counts the slaves before the break.
            if (auto own = wire::ConstFrameView::parse(main_copy.frame)) {
                for (const auto d : *own) {
                    if (d.command() == wire::Command::Brd) reachable = d.wkc();
                }
            }
        }
        if (!complete) {
            stats_.frames_lost.fetch_add(1, std::memory_order_relaxed);
            if (f.kind == FrameKind::Cyclic) all_complete = false;
            if (!lost_reported) {
                lost_reported = true;
                Event event{events::kFrameLost, cycle_, std::chrono::system_clock::now(),
                            static_cast<std::uint32_t>(f.kind), f.index, 0, 0};
                LostFrameDetail detail = f.detail;
                detail.main_returned = main_copy.path != CopyPath::Missing;
                detail.red_returned = red_copy.path != CopyPath::Missing;
                detail.encode_into(event);
                events_.push(event);
            }
            if (f.kind == FrameKind::Acyclic) acyclic_.complete(f.index, nullptr, now);
            continue;
        }

        if (f.kind == FrameKind::Acyclic) {
            acyclic_.complete(f.index, &*view, now);
            continue;
        }
        const auto result = exchange_.complete(f.index, *view, image_.inputs(), mismatches_);
        if (!result.layout_ok) all_complete = false;
        wkc_errors += result.wkc_errors;
    }
    in_flight_.clear();
    if (answered_brd) slaves_reached_.store(*answered_brd);
    if (sent_any) {
        if (any_returned) {
            cycles_without_return_.store(0);
        } else {
            cycles_without_return_.fetch_add(1);
        }
    }

    // Deviations that a topology change explains are counted as such, not raised as errors.
    const auto topology = topology_watch_.after_cycle(exchange_, mismatches_, expected_wkcs_pending_.load());
    if (topology.detected_now) {
        raise(events::kTopologyChangeDetected, topology.slaves_before.value_or(kNoCount),
              topology.slaves_now.value_or(kNoCount));
    }
    if (topology.attributed) {
        stats_.wkc_topology_deviations.fetch_add(wkc_errors, std::memory_order_relaxed);
    } else {
        stats_.wkc_errors.fetch_add(wkc_errors, std::memory_order_relaxed);
        for (const WkcMismatch& m : mismatches_) {
            const auto& datagrams = exchange_.plan().frames[m.frame].datagrams;
            raise(events::kCyclicWkcError, m.frame, static_cast<std::uint32_t>(m.datagram - datagrams.data()),
                  m.expected, m.received);
        }
    }
    inputs_valid_ = any_cyclic && all_complete && (mismatches_.empty() || topology.attributed);
    if (any_cyclic && !all_complete) stats_.cycles_incomplete.fetch_add(1, std::memory_order_relaxed);
    if (use_red() && any_returned) observe_ring(ring_closed, ring_broken, reachable);
}

// A frame counts only when it equals one pass through the whole ring: an
// unprocessed RED copy alone, or one side of a break alone, would put stale
// zeros into the inputs. Such a frame is lost for its cycle (acyclic
// requests go out again).
bool Master::is_complete(const InFlight& f, const ReturnedCopy& main_copy, const ReturnedCopy& red_copy,
                         const MergeResult& merged, const wire::ConstFrameView& view) const {
    if (f.sent_main && f.sent_red) {
        if (merged.complete) return true;
        // One copy bounced and the other vanished: the break sits right at a
        // master cable, so the bounced copy may still have passed every slave.
        // The working counters the ENI expects decide.
        return f.kind == FrameKind::Cyclic && (main_copy.path == CopyPath::BouncedMain || red_copy.path == CopyPath::BouncedRed) &&
               exchange_.counters_complete(f.index, view);
    }
    // Only one adapter could send: its copy came back processed on the same side.
    if (f.sent_main) return main_copy.path != CopyPath::Missing;
    if (f.sent_red) return red_copy.path == CopyPath::BouncedRed;
    return false;
}

void Master::observe_ring(bool closed, bool broken, std::optional<std::uint16_t> reachable) {
    const RingState previous = ring_state_.load();
    const RingState now = broken ? RingState::Broken : closed ? RingState::Closed : previous;
    if (now == RingState::Broken && previous == RingState::Broken) {
        // The first cycle of a break may not say where it is (the copy that
        // counts the slaves before it was lost in flight as the link went
        // down): the break is raised again, with its place, once a cycle finds it.
        if (reachable && reachable_from_main_.exchange(*reachable) != *reachable) {
            logger("master")->warn("line break located after slave {}", *reachable);
            raise(events::kLineBreak, *reachable, 1);
        }
        return;
    }
    if (now == RingState::Broken && reachable) reachable_from_main_.store(*reachable);
    if (now == previous) return;
    ring_state_.store(now);
    if (now == RingState::Broken) {
        if (!reachable) reachable_from_main_.store(kReachableUnknown);
        logger("master")->warn("line break{}", reachable ? fmt::format(" after slave {}", *reachable) : std::string());
        raise(events::kLineBreak, reachable.value_or(0), reachable ? 1 : 0);
    } else {
        reachable_from_main_.store(kReachableUnknown);
        if (previous == RingState::Broken) {
            logger("master")->info("line repaired: ring closed");
            raise(events::kLineRepaired);
        }
    }
}

void Master::set_expected_wkcs(std::vector<std::optional<std::uint16_t>> expected) {
    {
        std::lock_guard lock(expected_mutex_);
        expected_wkcs_ = std::move(expected);
    }
    expected_wkcs_pending_.store(true);
}

void Master::apply_requests() {
    if (expected_wkcs_pending_.load()) {
        // Copied into the exchange's fixed-size table; should the setter hold
        // the lock right now, the next cycle takes them.
        std::unique_lock lock(expected_mutex_, std::try_to_lock);
        if (lock.owns_lock()) {
            exchange_.set_expected(expected_wkcs_);
            expected_wkcs_pending_.store(false);
        }
    }
    const auto requested = requested_state_.load();
    const auto current = state_.load();
    if (requested != current) {
        state_.store(requested);
        logger("master")->info("master state {} -> {}", eni::to_string(current), eni::to_string(requested));
        raise(events::kMasterStateChanged, static_cast<std::uint32_t>(current), static_cast<std::uint32_t>(requested));
    }
    const bool sending = sending_requested_.load();
    if (sending != sending_.load()) {
        sending_.store(sending);
        logger("master")->info("sending {}", sending ? "enabled" : "stopped");
    }
}

void Master::send_frames(link::Clock::time_point now) {
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    const auto state = state_.load();
    for (std::size_t i = 0; i < exchange_.frame_count(); ++i) {
        if (!exchange_.active(i, state)) continue;
        const auto frame = exchange_.build(i, state, image_.outputs(), ethernet, tx_);
        send_copies(FrameKind::Cyclic, static_cast<std::uint16_t>(i), frame);
    }
    if (extension_) {
        Sender sender(*this);
        extension_->send_frames(sender, cycle_);
    }
    for (std::size_t k = 0; k < acyclic_.max_frames_per_cycle(); ++k) {
        wire::FrameBuilder builder(tx_, ethernet);
        const auto batch = acyclic_.fill_frame(builder, now);
        if (!batch) break;
        send_copies(FrameKind::Acyclic, *batch, builder.finish(), acyclic_.retry_index(*batch));
    }
    send_queued();
}

// Auto-increment addresses count slaves from where a frame is first
// processed. In a closed ring the RED copy is processed by nobody, so it may
// carry them as they are; beyond a break it is processed from the first
// slave after the break on, so its addresses are shifted by the number of
// slaves before the break. While that number is unknown the RED copy of such
// a frame is not sent (it would address the wrong slaves).
bool Master::prepare_red_copy(FrameKind kind, Bytes frame) const {
    if (kind != FrameKind::Acyclic) return true;
    auto view = wire::FrameView::parse(frame);
    if (!view) return false;
    const auto has_auto_increment = std::any_of(view->begin(), view->end(), [](const auto& d) {
        return wire::addressing_of(d.command()) == wire::Addressing::AutoIncrement;
    });
    if (!has_auto_increment) return true;
    // With MAIN down only this copy goes out: it passes the slaves unprocessed
    // to slave 1, whose port 0 has no link and loops it back, so processing
    // starts at slave 1 and the positions are as they are (the partner's death
    // leaves a new ACTIVE reaching its slaves through RED alone).
    if (!link_up(LinkRole::Main)) return true;
    const RingState ring = ring_state_.load();
    if (ring == RingState::Closed) return true;
    const auto reachable = reachable_from_main_.load();
    if (ring == RingState::Unknown || reachable == kReachableUnknown) return false;
    for (auto d : *view) {
        if (wire::addressing_of(d.command()) != wire::Addressing::AutoIncrement) continue;
        const auto h = d.header();
        d.set_address(wire::DatagramHeader::physical(static_cast<std::uint16_t>(h.adp() + reachable), h.ado()));
    }
    return true;
}

void Master::queue_copy(LinkRole role, ConstBytes frame, std::size_t owner) { tx_batches_->add(role, frame, owner); }

// The kernel reports carrier changes late (up to a second); a send that
// fails on a link without carrier is news of a pulled cable right now.
void Master::send_queued() {
    tx_batches_->flush(main_, use_red() ? red_ : nullptr, [this](LinkRole role, std::size_t owner, bool sent) {
        InFlight& f = sent_this_cycle_[owner];
        (role == LinkRole::Main ? f.sent_main : f.sent_red) = sent;
        (role == LinkRole::Main ? f.detail.sent_main : f.detail.sent_red) = sent;
        if (sent) return;
        // Refused by an adapter already known to be down is expected, not an error.
        if (link_up_[static_cast<std::size_t>(role)].load()) {
            stats_.send_errors.fetch_add(1, std::memory_order_relaxed);
            if (!link(role).link_up()) set_link_state(role, false);
        }
    });
}

void Master::send_copies(FrameKind kind, std::uint16_t index, Bytes frame, std::uint8_t retry_index) {
    const std::uint8_t id = tracker_.open(kind, index, cycle_, frame);
    auto set_source = [&](LinkRole role) {
        const auto mac = tracker_.source_mac(id, role, retry_index);
        std::copy(mac.bytes.begin(), mac.bytes.end(), frame.begin() + 6);
    };
    // Cyclic frames are tried on every adapter, whatever its link state is
    // believed to be: the news of a cable plugged back in may reach the
    // slaves before it reaches us, and a copy sent on RED alone would then
    // pass the closed ring unprocessed and the cycle's data would be lost. A
    // copy that vanishes into a dead cable costs nothing: the expected WKCs
    // tell whether the other, bounced copy passed every slave. Acyclic frames
    // have no expected WKC but are retried, so they go only where the link
    // is believed up. A copy counts as sent when the adapter took it: the
    // copies are queued, and send_queued() marks the entry pushed below.
    // A full batch leaves before any copy of this frame is queued (its entry is not pushed yet).
    if (tx_batches_->full(LinkRole::Main) || tx_batches_->full(LinkRole::Red)) send_queued();
    const std::size_t owner = sent_this_cycle_.size();
    const bool every_adapter = kind == FrameKind::Cyclic;
    if (every_adapter || link_up_[0].load()) {
        set_source(LinkRole::Main);
        queue_copy(LinkRole::Main, frame, owner);
    }
    if (use_red() && (every_adapter || link_up_[1].load()) && prepare_red_copy(kind, frame)) {
        set_source(LinkRole::Red);
        queue_copy(LinkRole::Red, frame, owner);
    }
    LostFrameDetail detail;
    detail.master_state = static_cast<std::uint8_t>(state_.load());
    if (kind == FrameKind::Acyclic) {
        if (const auto view = wire::ConstFrameView::parse(frame)) {
            for (const auto d : *view) {
                if (detail.datagrams++ > 0) continue;
                detail.first_command = d.command();
                detail.first_address = d.address();
                detail.first_length = static_cast<std::uint16_t>(d.length());
            }
        }
    }
    sent_this_cycle_.push_back(InFlight{id, kind, index, false, false, cycle_, detail});
    stats_.frames_sent.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace ecpair::master
