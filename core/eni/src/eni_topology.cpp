#include "ecpair/eni/eni_topology.hpp"

#include <algorithm>
#include <map>

namespace ecpair::eni {
namespace {

const PreviousPort* selected_previous_port(const Slave& slave) {
    const auto& ports = slave.previous_ports;
    const auto selected = std::find_if(ports.begin(), ports.end(), [](const PreviousPort& p) { return p.selected; });
    if (selected != ports.end()) return &*selected;
    return ports.empty() ? nullptr : &ports.front();
}

bool file_uses_previous_ports(const std::vector<Slave>& slaves) {
    for (std::size_t i = 1; i < slaves.size(); ++i) {
        if (!slaves[i].previous_ports.empty()) return true;
    }
    return false;
}

}  // namespace

char port_letter(int port) { return static_cast<char>('A' + port); }

bool is_floating_head(const std::vector<Slave>& slaves, std::size_t index) {
    const auto& slave = slaves[index];
    return index > 0 && slave.hot_connect && slave.previous_ports.empty() && file_uses_previous_ports(slaves);
}

EniTopology EniTopology::of(const std::vector<Slave>& slaves) {
    EniTopology topology;
    const std::size_t n = slaves.size();
    topology.attachments_.resize(n);
    topology.children_.resize(n);
    topology.floating_.assign(n, false);
    std::map<std::uint16_t, std::size_t> by_phys;
    for (std::size_t i = 0; i < n; ++i) by_phys.emplace(slaves[i].info.phys_addr, i);

    for (std::size_t i = 1; i < n; ++i) {
        if (is_floating_head(slaves, i)) {
            topology.floating_[i] = true;
            continue;
        }
        std::optional<Attachment> attachment;
        if (const auto* previous = selected_previous_port(slaves[i])) {
            const auto parent = by_phys.find(previous->phys_addr);
            const int port = previous->port - 'A';
            if (parent != by_phys.end() && parent->second != i && port >= 0 && port < kEscPorts) {
                attachment = Attachment{parent->second, port};
            }
        } else {
            attachment = Attachment{i - 1, 1};
        }
        if (!attachment) continue;  // the loader refuses such files; stay total anyway
        topology.attachments_[i] = attachment;
        auto& slot = topology.children_[attachment->parent][static_cast<std::size_t>(attachment->port)];
        if (!slot) slot = i;
    }
    return topology;
}

std::optional<std::size_t> EniTopology::child(std::size_t parent, int port) const {
    if (parent >= children_.size() || port < 0 || port >= kEscPorts) return std::nullopt;
    return children_[parent][static_cast<std::size_t>(port)];
}

}  // namespace ecpair::eni
