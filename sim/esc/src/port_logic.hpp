#pragma once
// The loop state of the four ports (datasheet I §3.1, esc-facts.md §3).
//
// Each port is Open, Closed or ClosedWait; next_port_state() is the whole
// transition rule:
//
//   not implemented, or loop setting Closed -> Closed
//   loop setting Open                       -> Open (even without link)
//   Auto                                    -> Open with link, Closed without
//   Auto-close: link lost                   -> Closed
//               link back                   -> ClosedWait (stays closed)
//               DL control written through another port, or a frame
//               received on this port while linked -> Open
//
// If no port is open, port 0 is opened as the recovery port: open() says so,
// loop_closed() keeps reporting the real state for the DL status register.
// Every state change is logged.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <spdlog/logger.h>

#include "ecpair/sim/esc.hpp"

namespace ecpair::sim {

enum class PortState : std::uint8_t { Closed, Open, ClosedWait };
enum class PortEvent : std::uint8_t { Reevaluate, LinkUp, LinkDown, LoopSettingWritten, FrameReceived };

std::string_view to_string(PortState state);
std::string_view to_string(PortEvent event);

PortState next_port_state(PortState current, LoopSetting setting, bool link, PortEvent event);

class PortLogic {
public:
    PortLogic(int implemented_ports, std::shared_ptr<spdlog::logger> log, std::string owner);

    // Power-on: every loop setting Auto, states from the current links.
    void reset();
    // New loop settings. `written_through` is the port the master's DL control
    // write entered by (it reopens auto-close ports waiting on the others);
    // nullopt when the ESC changes them itself (end of a temporary setting).
    void set_loop_settings(const std::array<LoopSetting, kMaxPorts>& settings, std::optional<int> written_through);
    // Returns true when an open port in Auto mode lost its link (lost-link counter).
    bool set_link(int port, bool up);
    void frame_received(int port);

    bool implemented(int port) const { return port >= 0 && port < implemented_; }
    bool link(int port) const { return ports_[index(port)].link; }
    LoopSetting setting(int port) const { return ports_[index(port)].setting; }
    // Whether frames leave and enter through the port (recovery included).
    bool open(int port) const;
    // The loop state as DL status reports it (recovery not included).
    bool loop_closed(int port) const { return ports_[index(port)].state != PortState::Open; }
    // Port 0 closed under Auto/Auto-close: the processing unit marks and
    // destroys circulating frames (datasheet I §3.5).
    bool circulating_frame_check() const;
    // A port in auto-close's closed wait: the next frame it receives opens it.
    bool any_closed_wait() const;
    // Counts the changes of any port's link or loop state: what depends on
    // them only (DL status) is recomputed when it moved, not for every frame.
    std::uint32_t version() const { return version_; }

private:
    struct Port {
        LoopSetting setting = LoopSetting::Auto;
        bool link = false;
        PortState state = PortState::Closed;
    };

    static std::size_t index(int port) { return static_cast<std::size_t>(port); }
    void apply(int port, PortEvent event);

    int implemented_;
    std::shared_ptr<spdlog::logger> log_;
    std::string owner_;
    std::array<Port, kMaxPorts> ports_{};
    std::uint32_t version_ = 0;
};

}  // namespace ecpair::sim
