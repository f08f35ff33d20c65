// The Hot-Connect worker (see the header). Two locks: mutex_ guards what
// other threads read or signal (flags, state, status) and is held only for
// moments, because the cycle thread wakes the worker through it; bus_work_
// serialises what talks to the slaves (a topology change, an operation) and
// guards Hot-Connect's knowledge of the bus (present_, counted_, flags_...).

#include "ecpair/hotconnect/hot_connect.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/bus/sii_writer.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/eni/eni_topology.hpp"
#include "ecpair/hotconnect/group_bring_up.hpp"
#include "ecpair/hotconnect/hot_connect_events.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sequencer/bus_identification_probe.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "hot_connect_scan.hpp"
#include "hotconnect_log.hpp"

namespace ecpair::hotconnect {
namespace {

using master::EventKind;
using sequencer::MasterState;

constexpr std::uint32_t kNoValue = 0x10000;

std::uint32_t port_number(char letter) { return static_cast<std::uint32_t>(letter - 'A'); }

std::uint32_t code(PortLoopReason reason) { return static_cast<std::uint32_t>(reason); }

OperationFailure failure(OperationError code, std::string message) { return OperationFailure{code, std::move(message)}; }

constexpr std::uint16_t kEcatEventMask = 0x0200;

std::optional<bus::DatagramReply> broadcast_read(bus::BusAccess& bus, std::uint16_t ado) {
    bus::DatagramRequest request;
    request.command = wire::Command::Brd;
    request.address = wire::DatagramHeader::physical(0, ado);
    request.data.assign(2, 0);
    auto reply = bus.exchange(request);
    if (!reply) return std::nullopt;
    return std::move(reply).value();
}

std::optional<std::uint16_t> count_slaves(bus::BusAccess& bus) {
    const auto reply = broadcast_read(bus, wire::reg::kAlStatus);
    if (!reply) return std::nullopt;
    return reply->wkc;
}

// The ECAT event mask the ENI's master InitCmds write, with the DL status event added.
std::uint16_t event_mask_of(const eni::EniConfig& eni) {
    std::uint16_t mask = master::kDlStatusEvent;
    for (const auto& cmd : eni.master.init_cmds) {
        if (cmd.command == wire::Command::Bwr && cmd.ado == kEcatEventMask && cmd.data.size() >= 2) {
            mask = static_cast<std::uint16_t>(mask | cmd.data[0] | (cmd.data[1] << 8));
        }
    }
    return mask;
}

}  // namespace

std::string_view to_string(OperationError error) {
    switch (error) {
        case OperationError::InvalidState: return "InvalidState";
        case OperationError::InvalidParam: return "InvalidParam";
        case OperationError::SlaveNotPresent: return "SlaveNotPresent";
        case OperationError::NotFound: return "NotFound";
        case OperationError::MasterRedStateInactive: return "MasterRedStateInactive";
        case OperationError::Failed: return "Failed";
    }
    return "?";
}

HotConnect::HotConnect(std::shared_ptr<const eni::EniConfig> eni, HotConnectHost& host, master::EventQueue* events,
                       HotConnectOptions options, sequencer::Clock& clock)
    : eni_(std::move(eni)),
      groups_(eni::HotConnectGroups::of(*eni_)),
      host_(host),
      events_(events),
      options_(options),
      clock_(clock),
      contributions_(WkcContributions::of(*eni_, host.plan())),
      event_mask_(event_mask_of(*eni_)),
      present_(eni_->slaves.size(), true),
      counted_(eni_->slaves.size(), true),
      flags_(eni_->slaves.size(), 0),
      shift_(eni_->slaves.size(), 0),
      group_up_(groups_.groups().size(), true),
      thread_([this](std::stop_token stop) { worker(stop); }) {
    log()->info("Hot-Connect: {} optional group(s), mode {}, border close {}, detection timeout {} ms",
                groups_.optional_count(), to_string(options_.mode), options_.border_close ? "on" : "off",
                options_.detection_timeout.count());
}

HotConnect::~HotConnect() {
    if (auto* watch = host_.topology_watch()) watch->disarm();
    thread_.request_stop();
    wake_.notify_all();
}

void HotConnect::set_presence_listener(PresenceListener listener) {
    std::lock_guard work(bus_work_);
    presence_listener_ = std::move(listener);
}

void HotConnect::raise(EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    if (events_) events_->push(master::Event{kind, host_.cycle(), std::chrono::system_clock::now(), a, b, c, d});
}

// ------------------------------------------------------------------ the master state machine

void HotConnect::on_startup_scan(const sequencer::ScanOutcome& outcome) {
    std::lock_guard work(bus_work_);
    const auto n = eni_->slaves.size();
    for (std::size_t i = 0; i < n; ++i) {
        const auto group = groups_.group_of(i);
        const auto state = group < outcome.groups.size() ? outcome.groups[group] : bus::GroupState::Present;
        present_[i] = outcome.present[i];
        counted_[i] = outcome.present[i];
        if (group == 0) {
            flags_[i] = master::kGroupPresent;
        } else {
            flags_[i] = state == bus::GroupState::Present ? master::kGroupPresent
                        : state == bus::GroupState::Refused ? master::kRefused
                                                            : 0;
        }
        shift_[i] = outcome.position_shift[i];
    }
    for (const auto& group : groups_.groups()) {
        group_up_[group.number] = group.number >= outcome.groups.size() || outcome.groups[group.number] == bus::GroupState::Present;
    }
    pending_.clear();
    answering_.store(outcome.report.responding);
    baseline_ = true;
    std::vector<MismatchView> mismatches;
    for (const auto& c : outcome.comparisons) {
        if (!c.is_mismatch()) continue;
        mismatches.push_back(mismatch_view(c));
        if (c.identification) {
            raise(master::events::kBusMismatchIdentification, c.position, c.identification->ado,
                  c.identification->read ? *c.identification->read : kNoValue, c.identification->expected);
        }
        if (c.previous_station && c.previous_port && c.previous_position) {
            raise(master::events::kBusMismatchPlace, c.position, *c.previous_station, port_number(*c.previous_port),
                  *c.previous_position);
        }
    }
    {
        std::lock_guard lock(mutex_);
        mismatches_ = std::move(mismatches);
    }
    publish_expected_wkcs();
    write_flags();
}

void HotConnect::on_sequence_busy() {
    {
        std::lock_guard lock(mutex_);
        armed_ = false;
    }
    if (auto* watch = host_.topology_watch()) watch->disarm();
}

void HotConnect::on_sequence_idle(MasterState reached, bool at_target) {
    const bool arm = at_target && reached != MasterState::Init;
    {
        std::lock_guard lock(mutex_);
        armed_ = arm && active_;
        master_state_ = reached;
        // Border close runs once the bus is up: the worker closes what it must.
        if (armed_ && options_.border_close) close_pending_ = true;
        if (armed_) events_pending_ = true;
    }
    if (auto* watch = host_.topology_watch()) {
        if (arm) {
            // On the cycle thread: it must never wait for the worker, so no lock. Should the
            // worker be between checking and waiting, it finds the flag at its next poll.
            watch->arm([this] {
                cycle_detected_.store(true);
                wake_.notify_all();
            });
        } else {
            watch->disarm();
        }
    }
    wake_.notify_all();
}

// ------------------------------------------------------------------ redundancy

void HotConnect::set_active(bool active) {
    {
        std::lock_guard lock(mutex_);
        active_ = active;
        if (!active) armed_ = false;
    }
    if (!active) {
        if (auto* watch = host_.topology_watch()) watch->disarm();
    }
    wake_.notify_all();
}

void HotConnect::after_takeover() {
    {
        std::lock_guard lock(mutex_);
        active_ = true;
        takeover_ = true;
    }
    const auto state = sequencer::to_master_state(host_.cyclic_state()).value_or(MasterState::Init);
    on_sequence_idle(state, true);
}

// ------------------------------------------------------------------ the worker

void HotConnect::worker(std::stop_token stop) {
    std::unique_lock lock(mutex_);
    while (!stop.stop_requested()) {
        wake_.wait_for(lock, stop, options_.poll_period,
                       [this] {
                           return detected_ || cycle_detected_.load() || accepted_ || takeover_ || close_pending_ ||
                                  events_pending_;
                       });
        if (stop.stop_requested()) return;
        const bool detected = std::exchange(detected_, false) || cycle_detected_.exchange(false);
        const bool accepted = std::exchange(accepted_, false);
        const bool takeover = std::exchange(takeover_, false);
        const bool close = std::exchange(close_pending_, false);
        const bool events = std::exchange(events_pending_, false);
        working_ = true;
        lock.unlock();
        if (events) enable_dl_status_events();
        handle(detected, accepted, takeover, close, stop);
        lock.lock();
        working_ = false;
        wake_.notify_all();
    }
}

void HotConnect::handle(bool detected, bool accepted, bool takeover, bool close, std::stop_token stop) {
    bool active = false;
    bool armed = false;
    ChangeState state{};
    {
        std::lock_guard lock(mutex_);
        active = active_;
        armed = armed_;
        state = state_;
    }
    if (!active) {
        follow_image();
        return;
    }
    if (!armed) return;
    std::unique_lock work(bus_work_);
    if (!baseline_) return;
    if (state == ChangeState::AwaitingAccept && accepted) {
        advance(ChangeInput::Accepted);
        const auto target = sequencer::to_master_state(host_.cyclic_state()).value_or(MasterState::Preop);
        bring_up_pending(target, false, stop);
        advance(ChangeInput::BroughtUp);
        close_borders();
        advance(ChangeInput::Closed);
        finish(change_result_);
        return;
    }
    // After a takeover: a change the image shows in progress is finished here.
    const bool unfinished = takeover && !pending_.empty();
    // The bus just came up with border close: a scan to know its free ports.
    const bool first_close = close && state == ChangeState::Idle;
    if (detected || unfinished || first_close || periodic_count_changed()) {
        if (state == ChangeState::AwaitingAccept || state == ChangeState::Idle) {
            advance(ChangeInput::Detected);
            run_change(stop);
        }
    }
}

// One BRD: a slave more or less, or a slave that saw a link change (its DL status event).
bool HotConnect::periodic_count_changed() {
    const auto reply = broadcast_read(host_.bus(), wire::reg::kAlStatus);
    return reply && (reply->wkc != answering_.load() || (reply->irq & master::kDlStatusEvent) != 0);
}

// Every slave passes its DL status event on in the IRQ field (0x0200 bit 2);
// reading DL status (a BRD of 0x0110) clears what is there already.
void HotConnect::enable_dl_status_events() {
    std::lock_guard work(bus_work_);
    std::vector<std::uint8_t> mask(2);
    store_le<std::uint16_t>(mask, 0, event_mask_);
    bus::DatagramRequest write;
    write.command = wire::Command::Bwr;
    write.address = wire::DatagramHeader::physical(0, kEcatEventMask);
    write.data = mask;
    if (auto r = host_.bus().exchange(write); !r) {
        log()->warn("Hot-Connect: ECAT event mask not written: {}", r.error().message);
        return;
    }
    (void)broadcast_read(host_.bus(), wire::reg::kDlStatus);
    log()->debug("Hot-Connect: DL status events enabled (ECAT event mask 0x{:04x})", event_mask_);
}

// INACTIVE: the ACTIVE's view arrives in the mirrored slave state image.
// Hot-Connect takes its knowledge from there and keeps the expected WKCs in
// step, so that a takeover starts with the right ones.
void HotConnect::follow_image() {
    std::lock_guard work(bus_work_);
    const auto image = host_.slaves().snapshot();
    bool any = false;
    std::uint16_t answering = 0;
    for (std::size_t i = 0; i < image.size() && i < present_.size(); ++i) {
        const auto& e = image[i];
        const bool waiting = (e.hot_connect & (master::kJoining | master::kAwaitingAccept)) != 0;
        flags_[i] = e.hot_connect;
        present_[i] = e.present && !waiting;
        counted_[i] = groups_.is_optional(i) ? ((e.hot_connect & master::kGroupPresent) != 0 && !waiting)
                                             : true;
        if (e.present || (e.hot_connect & (master::kRefused | master::kJoining | master::kAwaitingAccept)) != 0) ++answering;
        any = any || e.hot_connect != 0;
    }
    if (!any) return;  // nothing mirrored yet
    baseline_ = true;
    answering_.store(answering);
    pending_.clear();
    for (const auto& group : groups_.groups()) {
        if (!group.optional()) continue;
        const auto head = *group.head;
        const bool waiting = (flags_[head] & (master::kJoining | master::kAwaitingAccept)) != 0;
        group_up_[group.number] = (flags_[head] & master::kGroupPresent) != 0 && !waiting;
        if (waiting) pending_.push_back(group.number);
    }
    const auto expected = contributions_.expected(BusCount{counted_, present_, answering_.load()});
    if (expected != followed_) {
        followed_ = expected;
        host_.set_expected_wkcs(expected);
    }
}

void HotConnect::advance(ChangeInput input) {
    ChangeState from{};
    std::optional<ChangeState> next;
    {
        std::lock_guard lock(mutex_);
        from = state_;
        next = next_change_state(state_, input, options_.mode);
        if (next) state_ = *next;
    }
    wake_.notify_all();
    // Logged outside the lock: nothing waits for a log line.
    if (!next) {
        log()->debug("topology change: {} ignored in {}", to_string(input), to_string(from));
        return;
    }
    log()->info("topology change: {} -> {} ({})", to_string(from), to_string(*next), to_string(input));
}

// Settling through identification and the decision what to bring up; bus_work_ is held.
void HotConnect::run_change(std::stop_token stop) {
    // Found by the periodic count or forced: the cycle's deviations are the change's from now on too.
    if (auto* watch = host_.topology_watch()) watch->begin_change();
    change_started_ = clock_.now();
    deviations_at_start_ = host_.wkc_topology_deviations();
    change_result_ = TopologyResult::Ok;
    {
        std::lock_guard lock(mutex_);
        ++changes_;
    }
    const auto settled = settle(stop);
    if (!settled) {
        advance(stop.stop_requested() ? ChangeInput::Cancelled : ChangeInput::Timeout);
        finish(stop.stop_requested() ? TopologyResult::Cancelled : TopologyResult::Timeout);
        return;
    }
    advance(ChangeInput::Settled);

    auto scan = scan_for_hot_connect(host_.bus(), *eni_, present_);
    if (!scan) {
        const bool inactive = scan.error().code == bus::BusErrc::MasterRedStateInactive ||
                              scan.error().code == bus::BusErrc::Cancelled;
        log()->warn("topology change: scan failed: {}", scan.error().message);
        advance(ChangeInput::ScanFailed);
        finish(inactive ? TopologyResult::Cancelled : TopologyResult::ScanFailed);
        return;
    }
    sequencer::BusIdentificationProbe bus_probe(host_.bus(), clock_, *eni_, stop);
    HotConnectProbe probe(*scan, *eni_, bus_probe);
    last_report_ = std::move(scan->report);
    last_match_ = bus::match_topology(*last_report_, *eni_, groups_, probe);
    apply_match(*last_report_, *last_match_, true);

    if (pending_.empty()) {
        advance(ChangeInput::NothingNew);
        close_borders();
        advance(ChangeInput::Closed);
        finish(change_result_);
        return;
    }
    advance(ChangeInput::NewGroups);
    const auto target = sequencer::to_master_state(host_.cyclic_state()).value_or(MasterState::Preop);
    switch (options_.mode) {
        case HotConnectMode::Automatic:
            bring_up_pending(target, true, stop);
            advance(ChangeInput::BroughtUp);
            close_borders();
            advance(ChangeInput::Closed);
            finish(change_result_);
            return;
        case HotConnectMode::ManualPreop:
            bring_up_pending(MasterState::Preop, true, stop);
            advance(ChangeInput::BroughtUp);
            break;
        case HotConnectMode::ManualNoReset: break;
    }
    // Waiting for the operator: the groups stay out of the process data until accepted.
    std::uint32_t mask = 0;
    for (const auto g : pending_) {
        if (g <= 32) mask |= 1u << (g - 1);
        for (const auto m : groups_.group(g).members) {
            flags_[m] = static_cast<std::uint8_t>((flags_[m] & ~master::kJoining) | master::kAwaitingAccept);
        }
    }
    write_flags();
    // The expected WKCs leave the waiting groups out: deviations from now on are errors again.
    if (auto* watch = host_.topology_watch()) watch->settle();
    log()->warn("topology change: {} group(s) found, waiting for an accept (ecpairctl accept)", pending_.size());
    raise(events::kHotConnectAcceptPending, static_cast<std::uint32_t>(pending_.size()), mask);
}

// The slave count must hold still: two reads settle_gap apart that agree.
std::optional<std::uint16_t> HotConnect::settle(std::stop_token stop) {
    const auto deadline = clock_.now() + options_.detection_timeout;
    auto last = count_slaves(host_.bus());
    while (!stop.stop_requested()) {
        clock_.sleep_for(options_.settle_gap, stop);
        const auto now = count_slaves(host_.bus());
        if (now && last && *now == *last) return now;
        last = now;
        if (clock_.now() >= deadline) {
            log()->error("topology change: the slave count did not settle within {} ms", options_.detection_timeout.count());
            return std::nullopt;
        }
    }
    return std::nullopt;
}

void HotConnect::apply_match(const bus::ScanReport& report, const bus::TopologyMatch& match, bool report_events) {
    const auto present_now = match.present();
    const auto before = present_;
    bool added = false;
    bool removed = false;
    for (const auto& group : groups_.groups()) {
        const auto state = match.groups[group.number];
        const bool there = state == bus::GroupState::Present;
        const bool waiting = std::find(pending_.begin(), pending_.end(), group.number) != pending_.end();
        if (!group.optional()) {
            for (const auto m : group.members) {
                present_[m] = present_now[m];
                counted_[m] = true;  // a mandatory slave that is gone shows as cyclic WKC errors
                flags_[m] = present_now[m] ? master::kGroupPresent : 0;
            }
            if (state != bus::GroupState::Present) change_result_ = TopologyResult::MandatoryMissing;
            continue;
        }
        if (there && !group_up_[group.number] && !waiting) {
            pending_.push_back(group.number);
            added = true;
            log()->info("group {} '{}' found", group.number, group.name);
        }
        if (!there) {
            if (group_up_[group.number]) {
                removed = true;
                log()->warn("group {} '{}' is {}", group.number, group.name, bus::to_string(state));
            }
            group_up_[group.number] = false;
            pending_.erase(std::remove(pending_.begin(), pending_.end(), group.number), pending_.end());
            if (state == bus::GroupState::Refused && change_result_ == TopologyResult::Ok) {
                change_result_ = TopologyResult::GroupsRefused;
            }
        }
        const bool up = group_up_[group.number];
        for (const auto m : group.members) {
            present_[m] = there;
            counted_[m] = up;
            if (up) {
                flags_[m] = master::kGroupPresent;
            } else if (there) {
                flags_[m] = master::kGroupPresent | master::kJoining;
            } else {
                flags_[m] = state == bus::GroupState::Refused ? master::kRefused : 0;
            }
        }
    }
    for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
        if (match.position[i] && present_[i]) {
            shift_[i] = static_cast<std::uint16_t>(eni_->slaves[i].info.ring_position - *match.position[i]);
        }
    }
    answering_.store(report.responding);

    std::vector<MismatchView> mismatches;
    for (const auto& c : match.comparisons) {
        if (!c.is_mismatch()) continue;
        mismatches.push_back(mismatch_view(c));
        if (c.match == bus::SlaveMatch::Unexpected && change_result_ == TopologyResult::Ok) {
            change_result_ = TopologyResult::GroupsRefused;
        }
        log()->warn("bus mismatch: {}", c.describe());
    }
    {
        std::lock_guard lock(mutex_);
        mismatches_ = mismatches;
    }
    publish_expected_wkcs();
    write_flags();
    notify_presence();
    if (!report_events) return;

    raise(master::events::kBusScanStatus, report.responding, static_cast<std::uint32_t>(eni_->slaves.size()),
          mismatches.empty() ? 1 : 0);
    for (const auto& c : match.comparisons) {
        if (!c.is_mismatch()) continue;
        raise(master::events::kBusMismatch, c.position, static_cast<std::uint32_t>(c.match));
        if (c.identification) {
            raise(master::events::kBusMismatchIdentification, c.position, c.identification->ado,
                  c.identification->read ? *c.identification->read : kNoValue, c.identification->expected);
        }
        if (c.previous_station && c.previous_port && c.previous_position) {
            raise(master::events::kBusMismatchPlace, c.position, *c.previous_station, port_number(*c.previous_port),
                  *c.previous_position);
        }
    }
    for (std::size_t i = 0; i < present_.size(); ++i) {
        if (present_[i] != before[i]) {
            raise(master::events::kSlavePresence, static_cast<std::uint32_t>(i), present_[i] ? 1 : 0);
        }
    }
    std::uint32_t present_groups = 0;
    for (const auto& g : groups_.groups()) present_groups += g.optional() && match.groups[g.number] == bus::GroupState::Present;
    std::uint32_t mask = 0;
    for (const auto& g : groups_.groups()) {
        if (g.optional() && g.number <= 32 && match.groups[g.number] == bus::GroupState::Present) mask |= 1u << (g.number - 1);
    }
    const auto result = static_cast<std::uint32_t>(change_result_);
    const auto optional = static_cast<std::uint32_t>(groups_.optional_count());
    if (added) raise(events::kDetectAddGroups, result, optional, present_groups, mask);
    if (removed) raise(events::kProbeAllGroups, result, optional, present_groups, mask);
}

void HotConnect::bring_up_pending(MasterState target, bool reset_first, std::stop_token stop) {
    GroupBringUp bring_up(eni_, host_.bus(), clock_, [this](EventKind kind, std::uint32_t a, std::uint32_t b) { raise(kind, a, b); });
    const auto groups = pending_;
    for (const auto g : groups) {
        const auto& group = groups_.group(g);
        BringUpRequest request;
        request.slaves = group.members;
        request.position_shift = shift_;
        request.present = present_;
        request.target = target;
        request.reset_first = reset_first;
        const auto result = bring_up.run(request, [&] {
            for (const auto m : group.members) counted_[m] = true;
            publish_expected_wkcs();
        }, stop);
        if (!result.failure && result.reached == target) {
            std::vector<std::uint8_t> mask(2);
            store_le<std::uint16_t>(mask, 0, event_mask_);
            for (const auto m : group.members) {
                (void)bus::write_register(host_.bus(), bus::SlaveAddress::station(eni_->slaves[m].info.phys_addr),
                                          kEcatEventMask, mask);
            }
            if (target == sequencer::to_master_state(host_.cyclic_state()).value_or(target)) {
                group_up_[g] = true;
                pending_.erase(std::remove(pending_.begin(), pending_.end(), g), pending_.end());
                for (const auto m : group.members) flags_[m] = master::kGroupPresent;
            }
            continue;
        }
        // The group did not get there: it is left out; the descriptor says where it hangs (block node).
        change_result_ = TopologyResult::BringUpFailed;
        pending_.erase(std::remove(pending_.begin(), pending_.end(), g), pending_.end());
        for (const auto m : group.members) {
            counted_[m] = false;
            flags_[m] = master::kRefused;
        }
        MismatchView view;
        const auto failed = result.failure ? result.failure->slave : *group.head;
        view.configured = failed;
        view.match = bus::SlaveMatch::WrongIdentity;
        const auto head = *group.head;
        if (last_match_ && last_match_->position[head]) {
            view.position = *last_match_->position[head];
            for (const auto& c : last_match_->comparisons) {
                if (c.configured_index == head) {
                    view.previous_station = c.previous_station;
                    view.previous_port = c.previous_port;
                    view.previous_position = c.previous_position;
                }
            }
        }
        view.text = fmt::format("group {} '{}' did not reach {}: {}", g, group.name, sequencer::to_string(target),
                                result.failure ? result.failure->message : std::string("stopped"));
        {
            std::lock_guard lock(mutex_);
            mismatches_.push_back(view);
        }
        log()->error("topology change: {}", view.text);
    }
    publish_expected_wkcs();
    write_flags();
    notify_presence();
}

void HotConnect::close_borders() {
    if (!options_.border_close || !last_report_ || !last_match_) return;
    for (const auto& port : border_ports(*eni_, *last_report_, *last_match_)) {
        const auto key = std::make_pair(port.station, port.port);
        if (border_closed_.contains(key)) continue;
        if (auto set = set_loop_setting(host_.bus(), port.station, port.port, LoopSetting::Closed); !set) {
            log()->warn("border close: {}: {}", describe(port), set.error());
            continue;
        }
        border_closed_.insert(key);
        log()->info("border close: {} closed (no group may join there)", describe(port));
        raise(events::kPortLoopChanged, port.station, static_cast<std::uint32_t>(port.port),
              static_cast<std::uint32_t>(LoopSetting::Closed), code(PortLoopReason::BorderClose));
    }
}

void HotConnect::finish(TopologyResult result) {
    if (auto* watch = host_.topology_watch()) watch->settle();
    std::uint32_t present_groups = 0;
    for (const auto& g : groups_.groups()) present_groups += g.optional() && group_up_[g.number];
    const auto deviations = host_.wkc_topology_deviations() - deviations_at_start_;
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(clock_.now() - change_started_).count();
    log()->info("topology change done in {} ms: {}; {} of {} optional group(s) present, {} WKC deviation(s)", ms,
                to_string(result), present_groups, groups_.optional_count(), deviations);
    raise(events::kTopologyChangeDone, static_cast<std::uint32_t>(result), present_groups,
          static_cast<std::uint32_t>(groups_.optional_count()), static_cast<std::uint32_t>(deviations));
    std::lock_guard lock(mutex_);
    last_result_ = result;
    wake_.notify_all();
}

void HotConnect::publish_expected_wkcs() {
    host_.set_expected_wkcs(contributions_.expected(BusCount{counted_, present_, answering_.load()}));
}

void HotConnect::write_flags() {
    auto& image = host_.slaves();
    for (std::size_t i = 0; i < flags_.size() && i < image.size(); ++i) image.set_hot_connect(i, flags_[i], present_[i]);
}

void HotConnect::notify_presence() {
    if (!presence_listener_) return;
    std::vector<bool> taking_part(present_.size(), false);
    for (std::size_t i = 0; i < present_.size(); ++i) {
        taking_part[i] = present_[i] && (flags_[i] & (master::kJoining | master::kAwaitingAccept)) == 0;
    }
    presence_listener_(taking_part, shift_);
}

// ------------------------------------------------------------------ operations

std::optional<OperationFailure> HotConnect::refusal() const {
    std::lock_guard lock(mutex_);
    if (!active_) return failure(OperationError::MasterRedStateInactive, "this master is INACTIVE: ask the ACTIVE one");
    return std::nullopt;
}

std::optional<std::size_t> HotConnect::slave_of_station(std::uint16_t station) const {
    for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
        if (eni_->slaves[i].info.phys_addr == station) return i;
    }
    return std::nullopt;
}

Expected<void, OperationFailure> HotConnect::accept() {
    if (auto refused = refusal()) return unexpected(*refused);
    std::lock_guard lock(mutex_);
    if (state_ != ChangeState::AwaitingAccept) {
        return unexpected(failure(OperationError::InvalidState,
                                  fmt::format("no topology change waits for an accept (Hot-Connect is {})", to_string(state_))));
    }
    accepted_ = true;
    wake_.notify_all();
    return {};
}

Expected<void, OperationFailure> HotConnect::force_topology_change() {
    if (auto refused = refusal()) return unexpected(*refused);
    std::lock_guard lock(mutex_);
    if (!armed_) {
        return unexpected(failure(OperationError::InvalidState,
                                  "the master is not running at its target state (a sequence runs, or it is in INIT)"));
    }
    detected_ = true;
    wake_.notify_all();
    return {};
}

Expected<PortRef, OperationFailure> HotConnect::block_node(std::optional<std::size_t> mismatch,
                                                           std::optional<std::uint16_t> station) {
    if (auto refused = refusal()) return unexpected(*refused);
    std::lock_guard work(bus_work_);
    std::optional<PortRef> port;
    if (station) {
        const auto slave = slave_of_station(*station);
        if (!slave) return unexpected(failure(OperationError::NotFound, fmt::format("no slave with station {} in the ENI", *station)));
        const auto topology = eni::EniTopology::of(*eni_);
        const auto& attachment = topology.attachment(*slave);
        std::optional<std::pair<std::uint16_t, int>> where;
        if (last_match_) {
            for (const auto& c : last_match_->comparisons) {
                if (c.configured_index == slave && c.previous_station && c.previous_port) {
                    where = std::make_pair(*c.previous_station, static_cast<int>(port_number(*c.previous_port)));
                }
            }
        }
        if (!where && attachment) where = std::make_pair(eni_->slaves[attachment->parent].info.phys_addr, attachment->port);
        if (!where) {
            return unexpected(failure(OperationError::InvalidParam,
                                      fmt::format("station {} hangs on the master: there is no port in front of it to close", *station)));
        }
        port = PortRef{where->first, where->second};
    } else {
        std::vector<MismatchView> mismatches;
        {
            std::lock_guard lock(mutex_);
            mismatches = mismatches_;
        }
        const std::size_t index = mismatch.value_or(0);
        if (index >= mismatches.size()) {
            return unexpected(failure(mismatches.empty() ? OperationError::NotFound : OperationError::InvalidParam,
                                      mismatches.empty() ? std::string("there is no bus mismatch to block")
                                                         : fmt::format("mismatch {} does not exist (there are {})", index,
                                                                       mismatches.size())));
        }
        const auto& m = mismatches[index];
        if (!m.previous_station || !m.previous_port) {
            return unexpected(failure(OperationError::InvalidParam,
                                      fmt::format("mismatch {} names no previous slave and port: {}", index, m.text)));
        }
        port = PortRef{*m.previous_station, static_cast<int>(port_number(*m.previous_port))};
    }
    if (!slave_of_station(port->station)) {
        return unexpected(failure(OperationError::NotFound, fmt::format("no slave with station {} in the ENI", port->station)));
    }
    const auto parent = *slave_of_station(port->station);
    if (!present_[parent]) {
        return unexpected(failure(OperationError::SlaveNotPresent, fmt::format("station {} is not on the bus", port->station)));
    }
    if (auto set = set_loop_setting(host_.bus(), port->station, port->port, LoopSetting::Closed); !set) {
        return unexpected(failure(OperationError::Failed, set.error()));
    }
    log()->warn("block node: {} closed, what hangs behind it is cut off", describe(*port));
    raise(events::kPortLoopChanged, port->station, static_cast<std::uint32_t>(port->port),
          static_cast<std::uint32_t>(LoopSetting::Closed), code(PortLoopReason::BlockNode));
    std::lock_guard lock(mutex_);
    if (std::find(blocked_.begin(), blocked_.end(), *port) == blocked_.end()) blocked_.push_back(*port);
    return *port;
}

Expected<std::vector<PortRef>, OperationFailure> HotConnect::open_blocked_ports() {
    if (auto refused = refusal()) return unexpected(*refused);
    std::lock_guard work(bus_work_);
    std::vector<PortRef> blocked;
    {
        std::lock_guard lock(mutex_);
        blocked = blocked_;
    }
    std::vector<PortRef> opened;
    std::vector<PortRef> left;
    for (const auto& port : blocked) {
        if (auto set = set_loop_setting(host_.bus(), port.station, port.port, LoopSetting::Auto); !set) {
            log()->warn("open blocked ports: {}: {}", describe(port), set.error());
            left.push_back(port);
            continue;
        }
        opened.push_back(port);
        log()->info("open blocked ports: {} back to auto", describe(port));
        raise(events::kPortLoopChanged, port.station, static_cast<std::uint32_t>(port.port),
              static_cast<std::uint32_t>(LoopSetting::Auto), code(PortLoopReason::OpenBlocked));
    }
    std::lock_guard lock(mutex_);
    blocked_ = left;
    return opened;
}

Expected<void, OperationFailure> HotConnect::set_port(std::uint16_t station, int port, LoopSetting setting) {
    if (auto refused = refusal()) return unexpected(*refused);
    const auto slave = slave_of_station(station);
    if (!slave) return unexpected(failure(OperationError::NotFound, fmt::format("no slave with station {} in the ENI", station)));
    const int ports = static_cast<int>(std::max<std::size_t>(eni_->slaves[*slave].info.physics.size(), 2));
    if (port <= 0 || port >= ports) {
        return unexpected(failure(OperationError::InvalidParam,
                                  fmt::format("station {} has ports B..{} to set (port A leads to the master)", station,
                                              eni::port_letter(ports - 1))));
    }
    std::lock_guard work(bus_work_);
    if (!host_.slaves().get(*slave).present) {
        return unexpected(failure(OperationError::SlaveNotPresent, fmt::format("station {} is not on the bus", station)));
    }
    if (auto set = set_loop_setting(host_.bus(), station, port, setting); !set) {
        return unexpected(failure(OperationError::Failed, set.error()));
    }
    border_closed_.erase(std::make_pair(station, port));
    log()->info("station {} port {}: loop setting {} (operator)", station, eni::port_letter(port), to_string(setting));
    raise(events::kPortLoopChanged, station, static_cast<std::uint32_t>(port), static_cast<std::uint32_t>(setting),
          code(PortLoopReason::ByOperator));
    return {};
}

Expected<std::uint16_t, OperationFailure> HotConnect::set_alias(std::uint16_t station, std::uint16_t alias) {
    if (auto refused = refusal()) return unexpected(*refused);
    const auto slave = slave_of_station(station);
    if (!slave) return unexpected(failure(OperationError::NotFound, fmt::format("no slave with station {} in the ENI", station)));
    std::lock_guard work(bus_work_);
    if (!host_.slaves().get(*slave).present) {
        return unexpected(failure(OperationError::SlaveNotPresent, fmt::format("station {} is not on the bus", station)));
    }
    bus::SiiWriter writer(host_.bus());
    auto before = writer.set_station_alias(bus::SlaveAddress::station(station), alias);
    if (!before) return unexpected(failure(OperationError::Failed, before.error().message));
    log()->info("station {}: SII station alias {} -> {} (checksum rewritten; taken over at its next power-on)", station,
                *before, alias);
    return *before;
}

// ------------------------------------------------------------------ status

HotConnectStatus HotConnect::status() const {
    HotConnectStatus s;
    s.options = options_;
    s.groups = group_views(*eni_, groups_, host_.slaves().snapshot());
    std::lock_guard lock(mutex_);
    s.active = active_;
    s.state = state_;
    s.mismatches = mismatches_;
    s.blocked = blocked_;
    s.last_result = last_result_;
    s.changes = changes_;
    s.slaves_on_bus = answering_.load();
    return s;
}

bool HotConnect::wait_idle(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    return wake_.wait_for(lock, timeout, [this] {
        return (state_ == ChangeState::Idle || state_ == ChangeState::AwaitingAccept) && !detected_ &&
               !cycle_detected_.load() && !accepted_ &&
               !takeover_ && !close_pending_ && !events_pending_ && !working_;
    });
}

}  // namespace ecpair::hotconnect
