// The poll() loop of ecsim. Each round rebuilds the pollfd list (into a
// vector whose capacity is kept, so nothing is allocated once the control
// clients are stable), waits, then serves what is ready: the stop fd first,
// then frames, link changes and control requests. Frames go through the
// segment one at a time in one reusable buffer: receive, record, carry,
// queue for the exit side. The queued frames leave after each side's frames
// were carried (one send_batch per exit side) and are recorded then.

#include "segment_runner.hpp"

#include <poll.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <optional>
#include <system_error>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/sim/control_commands.hpp"
#include "ecpair/wire/constants.hpp"

namespace ecpair::ecsim {

namespace {

constexpr std::chrono::seconds kPcapFlushInterval{1};
// Frames served from one side before the loop looks at the other fds again.
constexpr int kFramesPerWakeup = 64;
// Frames queued per exit side: a wake-up's frames, each possibly duplicated by an impairment.
constexpr std::size_t kOutgoingCapacity = 2 * kFramesPerWakeup;

spdlog::logger& runner_log() {
    static const auto logger = ecpair::logger("ecsim");
    return *logger;
}

std::uint64_t nanoseconds(link::Clock::time_point time) {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count());
}

}  // namespace

Expected<std::unique_ptr<SegmentRunner>, std::string> SegmentRunner::create(RunnerSetup setup) {
    std::unique_ptr<SegmentRunner> runner(new SegmentRunner(std::move(setup)));
    SegmentRunner* self = runner.get();
    auto control = ControlServer::listen(self->setup_.control_path,
                                         [self](std::string_view line) { return self->handle_control(line); });
    if (!control) return unexpected(control.error().message);
    runner->control_ = std::move(control).value();
    return runner;
}

SegmentRunner::SegmentRunner(RunnerSetup setup)
    : setup_(std::move(setup)), outgoing_{link::FrameBatch(kOutgoingCapacity), link::FrameBatch(kOutgoingCapacity)} {}

SegmentRunner::~SegmentRunner() {
    if (setup_.pcap) setup_.pcap->flush();
}

std::string SegmentRunner::handle_control(std::string_view line) {
    const auto request = sim::parse_control_request(line);
    if (!request) return sim::control_error(request.error().message);
    // The clocks' truth is taken now, not at the last frame.
    setup_.segment.advance_time(nanoseconds(std::chrono::steady_clock::now()));
    if (request->command != sim::ControlCommand::Impair) {
        auto response = sim::execute_control_request(setup_.segment, *request);
        sync_carriers();
        return response;
    }
    const auto side = request->red_side ? sim::Side::Red : sim::Side::Main;
    const Impairment impairment{request->loss_percent, request->duplicate_percent,
                                std::chrono::microseconds(request->delay_us)};
    impairments_[static_cast<std::size_t>(side)].set(impairment);
    const auto text = fmt::format("{} cable: loss {}%, duplicates {}%, delay {} µs", request->red_side ? "RED" : "MAIN",
                                  impairment.loss_percent, impairment.duplicate_percent, impairment.delay.count());
    runner_log().info("impairment: {}", text);
    return sim::control_ok(text);
}

link::Link* SegmentRunner::link_of(sim::Side side) const {
    return side == sim::Side::Main ? setup_.main_link.get() : setup_.red_link.get();
}

void SegmentRunner::sync_side_links() {
    for (const sim::Side side : {sim::Side::Main, sim::Side::Red}) {
        const link::Link* link = link_of(side);
        setup_.segment.set_side_link(side, link != nullptr && link->link_up());
    }
}

void SegmentRunner::sync_carriers() {
    if (!setup_.set_carrier) return;
    for (const sim::Side side : {sim::Side::Main, sim::Side::Red}) {
        const link::Link* link = link_of(side);
        if (link == nullptr) continue;
        bool& taken_down = carrier_taken_down_[static_cast<std::size_t>(side)];
        const bool peer_alive = setup_.segment.side_peer_alive(side);
        // Down when the PHY went away; up only what this runner took down.
        if (peer_alive != taken_down) continue;
        auto changed = setup_.set_carrier(side, peer_alive);
        if (!changed) {
            runner_log().warn("{}: cannot take the carrier {}: {}", link->name(), peer_alive ? "up" : "down",
                              changed.error());
            continue;
        }
        taken_down = !peer_alive && *changed;
        if (!*changed) continue;
        if (peer_alive) {
            runner_log().info("{}: the {} side's PHY is back: carrier up", link->name(), sim::to_string(side));
        } else {
            runner_log().info("{}: the {} side faces no PHY (slave unpowered or cable cut): carrier down", link->name(),
                              sim::to_string(side));
        }
    }
}

void SegmentRunner::apply_link_changes(link::LinkStateSource& source) {
    for (const auto& change : source.read_changes()) {
        for (const sim::Side side : {sim::Side::Main, sim::Side::Red}) {
            const link::Link* link = link_of(side);
            if (link != nullptr && link->name() == change.interface) setup_.segment.set_side_link(side, change.up);
        }
    }
}

bool SegmentRunner::serve_side(sim::Side side) {
    link::Link& in = *link_of(side);
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    for (int served = 0; served < kFramesPerWakeup; ++served) {
        auto received = in.try_receive(buffer);
        if (!received) {
            runner_log().error("{}: {}", in.name(), received.error().message);
            return false;
        }
        if (!*received) return true;
        const link::ReceivedFrame& frame = **received;
        if (frame.wire_size > frame.size) {
            ++truncated_frames_;
            runner_log().warn("{}: a {}-byte frame does not fit the {}-byte buffer; dropped ({} so far)", in.name(),
                              frame.wire_size, buffer.size(), truncated_frames_);
            continue;
        }
        if (setup_.pcap) setup_.pcap->record(std::span(buffer).first(frame.size), frame.capture_time);
        // A frame that arrives is the PHY's news that the cable is back; the
        // kernel may announce the carrier only later.
        if (!setup_.segment.side_link(side) && in.link_up()) {
            runner_log().info("{}: carrier back (seen on receive)", in.name());
            setup_.segment.set_side_link(side, true);
        }

        auto& impairment = impairments_[static_cast<std::size_t>(side)];
        // A frame the cable "loses" on its way in reaches the first slave
        // damaged: that port counts it, and the master never gets it back.
        const int decided = impairment.copies();
        const auto condition = decided == 0 ? sim::FrameCondition::Damaged : sim::FrameCondition::Intact;
        const int copies = std::max(decided, 1);
        if (impairment.get().delay.count() > 0) {
            for (int c = 0; c < copies; ++c) {
                delayed_.push_back({std::chrono::steady_clock::now() + impairment.get().delay, side, condition,
                                    std::vector<std::uint8_t>(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(frame.size))});
            }
            continue;
        }
        if (copies == 2) {
            std::array<std::uint8_t, wire::kMaxFrameSizeVlan> twin = buffer;
            carry(side, twin, frame.size, nanoseconds(frame.timestamp), condition);
        }
        carry(side, buffer, frame.size, nanoseconds(frame.timestamp), condition);
    }
    return true;
}

void SegmentRunner::carry(sim::Side side, std::span<std::uint8_t> buffer, std::size_t size, std::uint64_t time_ns,
                          sim::FrameCondition condition) {
    const auto exit = setup_.segment.carry(side, buffer, size, time_ns, condition);
    if (!exit) return;
    const auto outgoing = std::span<const std::uint8_t>(buffer).first(size);
    // Damaged on its way out: the master's NIC drops it, no slave counts it.
    const int copies = impairments_[static_cast<std::size_t>(*exit)].copies();
    for (int c = 0; c < copies; ++c) send(*exit, outgoing);
}

void SegmentRunner::send(sim::Side exit, std::span<const std::uint8_t> outgoing) {
    if (link_of(exit) == nullptr) return;  // the segment never lets a frame out of a side without a link
    auto& batch = outgoing_[static_cast<std::size_t>(exit)];
    if (batch.full()) send_queued(exit);
    batch.append(outgoing);
}

void SegmentRunner::send_queued() {
    send_queued(sim::Side::Main);
    send_queued(sim::Side::Red);
}

// Frames after one the link refused are tried one by one, so each gets its
// own outcome.
void SegmentRunner::send_queued(sim::Side exit) {
    auto& batch = outgoing_[static_cast<std::size_t>(exit)];
    if (batch.empty()) return;
    link::Link& out = *link_of(exit);
    const auto frames = batch.frames();
    const auto result = out.send_batch(frames);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        if (i == result.sent) {
            on_send_failure(out, exit, result.error ? result.error->message : std::string("not sent"));
            continue;
        }
        if (i > result.sent) {
            if (auto sent = out.send(frames[i]); !sent) {
                on_send_failure(out, exit, sent.error().message);
                continue;
            }
        }
        if (setup_.pcap) setup_.pcap->record(frames[i], std::chrono::system_clock::now());
    }
    batch.clear();
}

void SegmentRunner::on_send_failure(link::Link& out, sim::Side exit, const std::string& reason) {
    ++send_failures_;
    runner_log().warn("{}: {} ({} send failures so far)", out.name(), reason, send_failures_);
    // The kernel tells carrier changes late; a failed send is the PHY's
    // news that the cable is gone: close the port now, not a second later.
    if (!out.link_up()) {
        runner_log().info("{}: carrier lost (seen on send)", out.name());
        setup_.segment.set_side_link(exit, false);
    }
}

void SegmentRunner::release_delayed() {
    const auto now = std::chrono::steady_clock::now();
    while (!delayed_.empty() && delayed_.front().due <= now) {
        auto& d = delayed_.front();
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
        std::copy(d.bytes.begin(), d.bytes.end(), buffer.begin());
        carry(d.side, buffer, d.bytes.size(), nanoseconds(link::Clock::now()), d.condition);
        delayed_.pop_front();
    }
}

// Until the pcap file is due for a flush, a delayed frame is due or an ESC's
// SM watchdog expires (-1: nothing is due, wait for a descriptor).
int SegmentRunner::poll_timeout_ms() const {
    const auto now = std::chrono::steady_clock::now();
    std::optional<std::chrono::steady_clock::time_point> due;
    const auto earliest = [&due](std::chrono::steady_clock::time_point at) {
        if (!due || at < *due) due = at;
    };
    if (setup_.pcap && setup_.pcap->has_unflushed()) earliest(next_flush_);
    if (!delayed_.empty()) earliest(delayed_.front().due);
    if (const auto deadline = setup_.segment.next_deadline()) {
        earliest(std::chrono::steady_clock::time_point(
            std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::nanoseconds(*deadline))));
    }
    if (!due) return -1;
    // Rounded up: waking before the deadline would only go round again.
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(*due - now);
    return left.count() < 0 ? 0 : static_cast<int>(left.count());
}

int SegmentRunner::run() {
    const int status = serve();
    if (setup_.pcap) setup_.pcap->flush();
    return status;
}

int SegmentRunner::serve() {
    sync_side_links();
    sync_carriers();
    runner_log().info("ecsim ready: {} slaves, MAIN on {}, RED on {}, control socket {}{}",
                      setup_.segment.slave_count(), setup_.main_link->name(),
                      setup_.red_link ? setup_.red_link->name() : std::string("(none)"), control_->path().string(),
                      setup_.pcap ? ", recording to " + setup_.pcap->path() : std::string());

    // Fixed slots first, then the control server's.
    enum Slot : std::size_t { kStop, kMain, kRed, kFirstLinkState };
    std::vector<pollfd> fds;
    next_flush_ = std::chrono::steady_clock::now() + kPcapFlushInterval;
    for (;;) {
        fds.clear();
        fds.push_back(pollfd{setup_.stop_fd, POLLIN, 0});
        fds.push_back(pollfd{setup_.main_link->selectable_fd(), POLLIN, 0});
        fds.push_back(pollfd{setup_.red_link ? setup_.red_link->selectable_fd() : -1, POLLIN, 0});
        for (const auto& source : setup_.link_states) fds.push_back(pollfd{source->selectable_fd(), POLLIN, 0});
        const std::size_t control_slot = fds.size();
        const std::size_t control_count = control_->append_poll_fds(fds);

        const int ready = ::poll(fds.data(), fds.size(), poll_timeout_ms());
        if (ready < 0) {
            if (errno == EINTR) continue;
            runner_log().error("poll: {}", std::error_code(errno, std::generic_category()).message());
            return kExitFailure;
        }
        if ((fds[kStop].revents & POLLIN) != 0) {
            runner_log().info("ecsim stopping");
            return kExitOk;
        }
        // Carrier changes first: a real ESC's PHY knows of a lost link before
        // the next frame's first bit, so frames that arrive in the same round
        // already meet the closed port.
        for (std::size_t i = 0; i < setup_.link_states.size(); ++i) {
            if (fds[kFirstLinkState + i].revents != 0) apply_link_changes(*setup_.link_states[i]);
        }
        if (fds[kMain].revents != 0 && !serve_side(sim::Side::Main)) return kExitFailure;
        send_queued();
        if (fds[kRed].revents != 0 && !serve_side(sim::Side::Red)) return kExitFailure;
        send_queued();
        control_->on_poll(std::span(fds).subspan(control_slot, control_count));
        release_delayed();
        send_queued();
        setup_.segment.advance_time(nanoseconds(std::chrono::steady_clock::now()));

        if (setup_.pcap && setup_.pcap->has_unflushed() && std::chrono::steady_clock::now() >= next_flush_) {
            setup_.pcap->flush();
            next_flush_ = std::chrono::steady_clock::now() + kPcapFlushInterval;
        }
    }
}

}  // namespace ecpair::ecsim
