// Ports beyond the implemented ones stay Closed whatever happens; everything
// else goes through next_port_state(), and apply() logs what changed.

#include "port_logic.hpp"

namespace ecpair::sim {

std::string_view to_string(PortState state) {
    switch (state) {
        case PortState::Closed: return "closed";
        case PortState::Open: return "open";
        case PortState::ClosedWait: return "closed (waiting to be reopened)";
    }
    return "?";
}

std::string_view to_string(PortEvent event) {
    switch (event) {
        case PortEvent::Reevaluate: return "loop setting";
        case PortEvent::LinkUp: return "link up";
        case PortEvent::LinkDown: return "link down";
        case PortEvent::LoopSettingWritten: return "DL control written";
        case PortEvent::FrameReceived: return "frame received";
    }
    return "?";
}

PortState next_port_state(PortState current, LoopSetting setting, bool link, PortEvent event) {
    switch (setting) {
        case LoopSetting::Open: return PortState::Open;
        case LoopSetting::Closed: return PortState::Closed;
        case LoopSetting::Auto: return link ? PortState::Open : PortState::Closed;
        case LoopSetting::AutoClose:
            if (!link) return PortState::Closed;
            if (event == PortEvent::LoopSettingWritten || event == PortEvent::FrameReceived) return PortState::Open;
            return current == PortState::Open ? PortState::Open : PortState::ClosedWait;
    }
    return PortState::Closed;
}

PortLogic::PortLogic(int implemented_ports, std::shared_ptr<spdlog::logger> log, std::string owner)
    : implemented_(implemented_ports), log_(std::move(log)), owner_(std::move(owner)) {}

void PortLogic::reset() {
    for (int p = 0; p < kMaxPorts; ++p) {
        Port& port = ports_[index(p)];
        port.setting = LoopSetting::Auto;
        port.state = PortState::Closed;
        if (implemented(p)) apply(p, PortEvent::Reevaluate);
    }
}

void PortLogic::set_loop_settings(const std::array<LoopSetting, kMaxPorts>& settings, std::optional<int> written_through) {
    for (int p = 0; p < kMaxPorts; ++p) {
        ports_[index(p)].setting = settings[index(p)];
        const bool reopens = written_through && *written_through != p;
        if (implemented(p)) apply(p, reopens ? PortEvent::LoopSettingWritten : PortEvent::Reevaluate);
    }
}

bool PortLogic::set_link(int port, bool up) {
    if (!implemented(port) || ports_[index(port)].link == up) return false;
    Port& p = ports_[index(port)];
    const bool counts_as_lost = !up && p.state == PortState::Open && p.setting == LoopSetting::Auto;
    p.link = up;
    ++version_;
    apply(port, up ? PortEvent::LinkUp : PortEvent::LinkDown);
    return counts_as_lost;
}

void PortLogic::frame_received(int port) {
    if (!implemented(port)) return;
    if (ports_[index(port)].state == PortState::ClosedWait) apply(port, PortEvent::FrameReceived);
}

bool PortLogic::open(int port) const {
    if (!implemented(port)) return false;
    if (ports_[index(port)].state == PortState::Open) return true;
    if (port != 0) return false;
    for (int p = 1; p < implemented_; ++p) {
        if (ports_[index(p)].state == PortState::Open) return false;
    }
    return true;  // every port closed: port 0 is the recovery port
}

bool PortLogic::circulating_frame_check() const {
    const Port& port0 = ports_[0];
    return port0.state != PortState::Open &&
           (port0.setting == LoopSetting::Auto || port0.setting == LoopSetting::AutoClose);
}

bool PortLogic::any_closed_wait() const {
    for (int p = 0; p < implemented_; ++p) {
        if (ports_[index(p)].state == PortState::ClosedWait) return true;
    }
    return false;
}

void PortLogic::apply(int port, PortEvent event) {
    Port& p = ports_[index(port)];
    const PortState next = next_port_state(p.state, p.setting, p.link, event);
    if (next == p.state) return;
    log_->info("{}: port {} {} -> {} ({})", owner_, port, to_string(p.state), to_string(next), to_string(event));
    p.state = next;
    ++version_;
}

}  // namespace ecpair::sim
