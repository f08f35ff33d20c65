#include "ecpair/hotconnect/port_control.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/bus/dl_ports.hpp"
#include "ecpair/eni/eni_topology.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::hotconnect {

std::string_view to_string(LoopSetting setting) {
    switch (setting) {
        case LoopSetting::Auto: return "auto";
        case LoopSetting::AutoClose: return "auto-close";
        case LoopSetting::Open: return "open";
        case LoopSetting::Closed: return "closed";
    }
    return "?";
}

std::optional<LoopSetting> loop_setting_from(std::string_view word) {
    if (word == "auto") return LoopSetting::Auto;
    if (word == "auto-close") return LoopSetting::AutoClose;
    if (word == "open") return LoopSetting::Open;
    if (word == "closed") return LoopSetting::Closed;
    return std::nullopt;
}

std::string describe(const PortRef& port) {
    return fmt::format("station {} port {}", port.station, eni::port_letter(port.port));
}

Expected<void, std::string> set_loop_setting(bus::BusAccess& bus, std::uint16_t station, int port, LoopSetting setting) {
    const auto slave = bus::SlaveAddress::station(station);
    auto current = bus::read_register(bus, slave, wire::reg::kDlControlLoop, 1);
    if (!current) return unexpected(current.error().message);
    if (current->wkc != 1) return unexpected(fmt::format("station {} does not answer", station));
    const unsigned shift = static_cast<unsigned>(2 * port);
    const auto loop = static_cast<std::uint8_t>((current->data[0] & ~(0x03u << shift)) |
                                                (static_cast<unsigned>(setting) << shift));
    // Closing the port a frame left by loses that frame on its way back: the
    // write may look lost although the slave took it. Read it back then.
    auto written = bus::write_register(bus, slave, wire::reg::kDlControlLoop, {loop});
    if (written && written->wkc == 1) return {};
    auto check = bus::read_register(bus, slave, wire::reg::kDlControlLoop, 1);
    if (check && check->wkc == 1 && check->data[0] == loop) return {};
    if (!written) return unexpected(written.error().message);
    return unexpected(fmt::format("station {} did not take the loop setting", station));
}

std::vector<PortRef> border_ports(const eni::EniConfig& eni, const bus::ScanReport& report,
                                  const bus::TopologyMatch& match) {
    const auto topology = eni::EniTopology::of(eni);
    std::vector<PortRef> ports;
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        const auto& at = match.position[i];
        if (!at || *at >= report.slaves.size() || !report.slaves[*at].dl_status_read) continue;
        const bus::DlPorts dl{report.slaves[*at].dl_status};
        const int implemented = static_cast<int>(std::max<std::size_t>(eni.slaves[i].info.physics.size(), 2));
        for (const int p : eni::kDownstreamPorts) {
            if (p >= implemented || topology.child(i, p)) continue;
            // What hangs there on the bus: a configured slave stays; the RED side (link, nothing found) stays.
            bool keep = false;
            bool found_behind = false;
            for (const auto& c : match.comparisons) {
                if (c.previous_position != *at || c.previous_port != eni::port_letter(p)) continue;
                found_behind = true;
                keep = c.configured_index.has_value();
            }
            if (!found_behind && dl.downstream(p)) keep = true;
            if (!keep) ports.push_back(PortRef{eni.slaves[i].info.phys_addr, p});
        }
    }
    return ports;
}

}  // namespace ecpair::hotconnect
