// How a frame travels through the simulated segment, and the ESCs' time.
//
// A frame moves by a small state machine over three steps (frame_walk.hpp),
// repeated until it leaves at a side or dies:
//
//   Transmit(end)      the frame leaves by `end` (a side, or an open slave
//                      port) over its cable. No cable, a cut cable or a dead
//                      far end (unpowered slave, side without carrier): lost.
//                      Reaching a side: the frame leaves the segment there.
//                      Reaching a slave port: the ESC is told (DC latch,
//                      auto-close's closed wait); if that port was closed the
//                      frame is lost, else it goes on inside that ESC:
//                      port 0 -> Epu, port p -> Loopback(next_port(p)).
//   Loopback(slave, p) the ESC's loopback function of port p: an open port
//                      sends the frame out (Transmit); a closed one passes
//                      it to the next port, and a closed port 0 hands it
//                      into the processing unit (Epu).
//   Epu(slave)         the processing unit works on the frame (or destroys
//                      it), then it goes to Loopback(3), the port after the
//                      EPU in every ESC's order.
//
// An ESC forwards a frame while it streams through, so the frame's own
// register writes (a new loop setting in 0x0101, applied by the ESC at the
// end of the frame) cannot change the way this frame leaves that ESC: the
// loopbacks after an EPU pass use the ports' states from before it.
//
// The frame's time: each ESC keeps it for its forwarding or processing
// delay (by the port it leaves by, EscDelays), each cable for the cable
// delay (SegmentOptions::propagation); the ESCs take their DC receive times
// and processing-unit times from it.
//
// Damaged frames (a port's PHY error, inject_rx_errors; a frame that came in
// damaged, FrameCondition::Damaged): the first port to receive one damaged
// counts an invalid frame and an RX error, every later port a forwarded RX
// error; no EPU processes it, it opens no port and latches nothing, and at a
// side it is dropped (damaged_dropped), as the master's NIC would drop it.
// While any port error is pending, frames go step by step.
//
// While the port states stay fixed, each step has exactly one predecessor,
// so a frame's path cannot run into a loop that avoids its entry: it always
// ends at a side (or dies). The bound on the steps (kStepsPerSlave per
// slave) is a guard against an ESC that changes its mind mid-frame.
//
// The fast pass. In a segment of hundreds of slaves a cyclic frame addresses
// a few of them, yet every ESC it passes would be called, and each call
// touches that ESC's own register file: at 512 slaves a cache miss per slave
// and frame. So while ports stay as they are, the path from each side is
// recorded once (FrameRoute), and a frame follows it calling only the ESCs
// it may address (FrameAddressing, from the frame's datagrams and each ESC's
// PassDigest) and the ESCs that are not passable; what the others would have
// done to the frame (ADP, IRQ, the forwarding bit) is applied in one go. An
// ESC that is called is digested again; when that changes its ports or
// power, the routes are forgotten and the frame goes on step by step from
// where it is. The walk is exactly the step machine's, so a master cannot
// tell the two apart; the tests compare them byte for byte, register for
// register (the one difference, DC's system time copy in 0x0910, is read
// only by frames that address the ESC, which take it anew).

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <limits>

#include "ecpair/sim/segment.hpp"
#include "fast_pass.hpp"
#include "frame_walk.hpp"
#include "segment_log.hpp"

namespace ecpair::sim {
namespace {

using detail::segment_log;
using detail::WalkEnd;
using detail::WalkResult;
using detail::WalkState;

// An upper bound on the steps a frame may take per slave: each port of a
// slave is reached at most once, each arrival a few steps.
constexpr std::size_t kStepsPerSlave = 32;

// Whether the per-frame debug lines are wanted; checked before building
// their text, so that carry() allocates nothing when they are not.
bool tracing_frames() { return segment_log().should_log(spdlog::level::debug); }

std::size_t side_index(Side side) { return static_cast<std::size_t>(side); }

}  // namespace

// ------------------------------------------------------------------ time

void Segment::advance_time(std::uint64_t now_ns) {
    note_time(now_ns);
    if (!options_.fast_pass) {
        for (auto& esc : escs_) esc.advance_time(now_ns);
        return;
    }
    // An ESC's clock matters only for its watchdog, whose deadline the digest holds.
    for (std::size_t s = 0; s < escs_.size(); ++s) {
        if (fast_->digests[s].deadline_ns > now_ns) continue;
        escs_[s].advance_time(now_ns);
        refresh_digest(s);
    }
}

std::optional<std::uint64_t> Segment::next_deadline() const {
    std::optional<std::uint64_t> earliest;
    for (std::size_t s = 0; s < escs_.size(); ++s) {
        const auto deadline =
            options_.fast_pass ? std::optional(fast_->digests[s].deadline_ns) : escs_[s].next_deadline();
        if (!deadline || *deadline == std::numeric_limits<std::uint64_t>::max()) continue;
        if (!earliest || *deadline < *earliest) earliest = deadline;
    }
    return earliest;
}

// ------------------------------------------------------------------ digests

void Segment::refresh_digest(std::size_t slave) {
    if (!options_.fast_pass) return;
    const PassDigest next = escs_[slave].pass_digest();
    PassDigest& current = fast_->digests[slave];
    if (next.open_ports != current.open_ports || next.powered != current.powered) fast_->forget_routes();
    if (next.passable != current.passable) {
        if (next.passable) {
            --fast_->not_passable;
        } else {
            ++fast_->not_passable;
        }
    }
    current = next;
}

void Segment::refresh_digests() {
    if (!options_.fast_pass) return;
    fast_->digests.resize(escs_.size());
    fast_->called.assign(escs_.size(), 0);
    fast_->calls.reserve((kPortCount + 1) * escs_.size());
    fast_->not_passable = 0;
    for (std::size_t s = 0; s < escs_.size(); ++s) {
        fast_->digests[s] = escs_[s].pass_digest();
        if (!fast_->digests[s].passable) ++fast_->not_passable;
    }
    for (auto& route : fast_->routes) route.reserve(escs_.size());
    fast_->forget_routes();
}

// ------------------------------------------------------------------ carry

std::optional<Side> Segment::carry(Side entry, Bytes buffer, std::size_t& size, std::uint64_t now_ns,
                                   FrameCondition condition) {
    assert(buffer.size() >= wire::kMinFrameSize && size <= buffer.size());
    size = wire::pad_to_minimum(buffer, size);
    note_time(now_ns);
    ++counters_.sides[side_index(entry)].frames_in;
    // A frame from a side proves that side's carrier is up. ecsim reads carrier
    // changes between batches, so a master's first frames after a plug can
    // come before the news; without this they went round the ring and out of a
    // side still thought dead (lost_no_link), which a real ESC never does.
    if (!side_link_[side_index(entry)]) set_side_link(entry, true);

    auto parsed = wire::FrameView::parse(buffer.first(size));
    const bool not_ethercat = !parsed && parsed.error().code == wire::DecodeErrc::NotEtherCat;
    if (!parsed && !not_ethercat) {
        ++counters_.unprocessable;
        if (tracing_frames()) {
            segment_log().debug("frame from {}: {}; forwarded without processing", to_string(entry),
                                parsed.error().describe());
        }
    }
    const std::uint64_t seq = next_frame_seq_++;
    // A damaged frame, or one that may be damaged on its way, goes step by
    // step: every port it reaches counts it.
    detail::FrameHealth health =
        condition == FrameCondition::Damaged ? detail::FrameHealth::Damaged : detail::FrameHealth::Intact;
    if (parsed && options_.fast_pass && health == detail::FrameHealth::Intact && rx_errors_pending_ == 0) {
        if (const auto result = walk_fast(entry, parsed.value(), now_ns, seq)) return finish(*result, entry, seq);
    }
    WalkState state;
    state.leaving = Endpoint::of_side(entry);
    state.time_ns = now_ns;
    const WalkResult result = walk_through_escs(state, parsed ? &parsed.value() : nullptr, !not_ethercat, seq, health);
    return finish(result, entry, seq, health);
}

WalkResult Segment::walk_through_escs(WalkState& state, wire::FrameView* frame, bool ethercat, std::uint64_t seq,
                                      detail::FrameHealth& health) {
    // The wire's questions answered by the ESCs themselves.
    struct EscPolicy {
        Segment& segment;
        wire::FrameView* frame;  // null: not a valid EtherCAT datagram frame
        bool ethercat;           // EtherType 0x88A4 (with frame null: unprocessable, forwarded untouched)
        std::uint64_t seq;
        detail::FrameHealth& health;

        bool cable_has_link(std::size_t cable) const { return segment.cable_has_link(cable); }
        bool port_open(std::size_t slave, int port) const { return segment.escs_[slave].port_open(port); }
        std::uint64_t leaving_ns(std::size_t slave, int port, bool through_epu) const {
            return segment.escs_[slave].propagation_delays().leaving(port, through_epu);
        }
        std::uint64_t cable_ns(std::size_t /*cable*/) const { return segment.options_.propagation.cable_ns; }
        void arrived(std::size_t slave, int port, std::uint64_t time_ns) {
            Esc& esc = segment.escs_[slave];
            if (health == detail::FrameHealth::Intact && segment.rx_errors_pending_ != 0 && esc.take_rx_error(port)) {
                --segment.rx_errors_pending_;
                health = detail::FrameHealth::Damaged;
            }
            if (health != detail::FrameHealth::Intact) {
                // The first port to receive it damaged counts an invalid frame
                // and marks it; every later one counts a forwarded error.
                esc.damaged_frame_arrived_at_port(port, health == detail::FrameHealth::Marked);
                health = detail::FrameHealth::Marked;
                return;
            }
            esc.frame_arrived_at_port(port, time_ns, seq);
            segment.refresh_digest(slave);
        }
        bool epu(std::size_t slave, std::uint64_t time_ns) {
            Esc& esc = segment.escs_[slave];
            // A damaged frame passes the processing unit without effect: an ESC
            // takes no write of a frame whose FCS is wrong, and the master drops it.
            if (health != detail::FrameHealth::Intact) return esc.powered();
            EpuVerdict verdict = EpuVerdict::Forward;
            if (frame != nullptr) {
                verdict = esc.process(*frame, FrameContext{time_ns, seq});
                segment.watch_dc(slave, time_ns);
                if (verdict == EpuVerdict::Destroy) ++segment.counters_.destroyed_circulating;
            } else if (!ethercat) {
                verdict = esc.process_non_ethercat();
                if (verdict == EpuVerdict::Destroy) ++segment.counters_.non_ethercat_dropped;
            }
            segment.refresh_digest(slave);
            return verdict == EpuVerdict::Forward;
        }
    };
    EscPolicy policy{*this, frame, ethercat, seq, health};
    return detail::walk(topology_, state, policy, kStepsPerSlave * (escs_.size() + 1));
}

std::optional<WalkResult> Segment::walk_fast(Side entry, wire::FrameView& frame, std::uint64_t now_ns,
                                             std::uint64_t seq) {
    detail::FastPass& fast = *fast_;
    detail::FrameAddressing& addressing = fast.addressing;
    if (!addressing.summarise(frame)) return std::nullopt;
    const std::size_t side = side_index(entry);
    detail::FrameRoute& route = fast.routes[side];
    if (!fast.route_valid[side]) {
        const auto link = [this](std::size_t cable) { return cable_has_link(cable); };
        if (!route.record(topology_, fast.digests, entry, link, options_.propagation.cable_ns,
                          kStepsPerSlave * (escs_.size() + 1))) {
            return std::nullopt;
        }
        fast.route_valid[side] = true;
    }
    // A route through no EPU (the RED copy in a closed ring) past passable ESCs only: nothing on
    // it does anything to the frame.
    if (route.epu_count() == 0 && fast.not_passable == 0) return route.end();

    // Which ESCs process the frame: those not passable, and those whose EPU
    // the route passes that a datagram may address or whose watchdog runs out
    // by the frame's last EPU time. The ESCs of one frame do not change one
    // another, so this is decided before any is called.
    const std::uint64_t last_epu_ns = now_ns + route.last_epu_after_ns();
    const std::span<const detail::RouteStep> steps = route.steps();
    fast.calls.clear();
    std::uint64_t passed = 0;
    for (const detail::RouteSlave& on_route : route.slaves()) {
        const PassDigest& digest = fast.digests[on_route.slave];
        const bool through_epu = on_route.epu_pass != detail::RouteSlave::kNoEpu;
        if (!digest.passable || (through_epu && (digest.deadline_ns <= last_epu_ns ||
                                                 addressing.addresses(digest, on_route.epu_pass)))) {
            fast.called[on_route.slave] = seq;
            const bool arrivals = !digest.passable || addressing.needs_arrivals(digest);
            for (std::uint8_t k = 0; k < on_route.step_count; ++k) {
                const std::uint32_t index = on_route.steps[k];
                if (arrivals || steps[index].kind == detail::RouteStep::Kind::Epu) fast.calls.push_back(index);
            }
        } else if (through_epu) {
            addressing.passed(digest);
            ++passed;
        }
    }
    std::sort(fast.calls.begin(), fast.calls.end());

    for (const std::uint32_t index : fast.calls) {
        const detail::RouteStep& step = steps[index];
        const std::size_t slave = step.slave;
        const std::uint64_t time_ns = now_ns + step.after_ns;
        if (step.kind == detail::RouteStep::Kind::Epu) {
            const std::uint8_t ports_before = fast.digests[slave].open_ports;
            addressing.set_auto_increment(frame, step.epus_before);
            const EpuVerdict verdict = escs_[slave].process(frame, FrameContext{time_ns, seq});
            watch_dc(slave, time_ns);
            refresh_digest(slave);
            if (verdict == EpuVerdict::Destroy) {
                ++counters_.destroyed_circulating;
                counters_.epus_passed += passed;
                return WalkResult{WalkEnd::Destroyed, {}, slave};
            }
            if (fast.route_valid[side]) continue;
            WalkState rest = resume_after(step, slave, time_ns);
            rest.step = detail::WalkStep::Loopback;
            rest.port = next_port(0);
            rest.through_epu = true;
            rest.open_before_epu.emplace();
            for (int p = 0; p < kPortCount; ++p) {
                (*rest.open_before_epu)[static_cast<std::size_t>(p)] = (ports_before & (1U << p)) != 0;
            }
            apply_passed_before(route, index, frame, seq);
            detail::FrameHealth intact = detail::FrameHealth::Intact;  // the fast pass carries whole frames only
            return walk_through_escs(rest, &frame, true, seq, intact);
        }
        // An arrival changes an ESC only through a port in closed wait, and
        // then the ESC was not passable.
        const bool was_passable = fast.digests[slave].passable;
        escs_[slave].frame_arrived_at_port(step.port, time_ns, seq);
        if (!was_passable) refresh_digest(slave);
        // A route that ends at a closed port ends with that arrival: the frame is lost there.
        const bool lost_here = index + 1 == steps.size() && route.end().end == WalkEnd::LostClosedPort;
        if (fast.route_valid[side] || lost_here) continue;
        WalkState rest = resume_after(step, slave, time_ns);
        rest.step = step.port == 0 ? detail::WalkStep::Epu : detail::WalkStep::Loopback;
        rest.port = next_port(step.port);
        addressing.set_auto_increment(frame, step.epus_before);
        apply_passed_before(route, index, frame, seq);
        detail::FrameHealth intact = detail::FrameHealth::Intact;
        return walk_through_escs(rest, &frame, true, seq, intact);
    }
    addressing.set_auto_increment(frame, route.epu_count());
    addressing.apply_passed(frame);
    counters_.epus_passed += passed;
    return route.end();
}

detail::WalkState Segment::resume_after(const detail::RouteStep& step, std::size_t slave, std::uint64_t time_ns) {
    WalkState rest;
    rest.slave = slave;
    rest.time_ns = time_ns;
    rest.steps = step.walked;
    return rest;
}

// The route stops holding at step `index`: only the ESCs passed before it
// have left their marks in the frame.
void Segment::apply_passed_before(const detail::FrameRoute& route, std::uint32_t index, wire::FrameView& frame,
                                  std::uint64_t seq) {
    detail::FastPass& fast = *fast_;
    fast.addressing.forget_passed();
    for (const detail::RouteSlave& on_route : route.slaves()) {
        if (on_route.epu_pass == detail::RouteSlave::kNoEpu || on_route.epu_step >= index) continue;
        if (fast.called[on_route.slave] == seq) continue;
        fast.addressing.passed(fast.digests[on_route.slave]);
        ++counters_.epus_passed;
    }
    fast.addressing.apply_passed(frame);
}

std::optional<Side> Segment::finish(const WalkResult& result, Side entry, std::uint64_t seq,
                                   detail::FrameHealth health) {
    switch (result.end) {
        case WalkEnd::Left:
            if (health != detail::FrameHealth::Intact) {
                ++counters_.damaged_dropped;
                if (tracing_frames()) {
                    segment_log().debug("frame {} from {} reached {} damaged: dropped (wrong FCS)", seq,
                                        to_string(entry), to_string(result.where.side));
                }
                return std::nullopt;
            }
            ++counters_.sides[side_index(result.where.side)].frames_out;
            return result.where.side;
        case WalkEnd::LostNoLink:
            ++counters_.lost_no_link;
            if (tracing_frames()) {
                segment_log().debug("frame {} from {} lost: {} has no link", seq, to_string(entry),
                                    describe(result.where));
            }
            return std::nullopt;
        case WalkEnd::LostClosedPort:
            ++counters_.lost_closed_port;
            if (tracing_frames()) {
                segment_log().debug("frame {} from {} lost: {} is closed", seq, to_string(entry),
                                    describe(result.where));
            }
            return std::nullopt;
        case WalkEnd::Destroyed:
            segment_log().debug("frame {} from {} destroyed by the EPU of slave {}", seq, to_string(entry),
                                result.slave + 1);
            return std::nullopt;
        case WalkEnd::HopLimit: break;
    }
    ++counters_.hop_limit_exceeded;
    segment_log().warn("frame {} from {} still travelling after {} steps: dropped", seq, to_string(entry),
                       kStepsPerSlave * (escs_.size() + 1));
    return std::nullopt;
}

}  // namespace ecpair::sim
