// The simulated segment's construction, its links and the faults; how a
// frame travels through it is segment_carry.cpp.
//
// Physical links are derived, never stored here: a port has link when its
// cable is intact and both ends are alive (slave powered, side with
// carrier). update_links() pushes changes into the ESCs after every fault,
// and takes the ESCs' pass digests again.

#include "ecpair/sim/segment.hpp"

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/eni/eni_topology.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/sim/foe_server.hpp"
#include "ecpair/wire/frame.hpp"
#include "dc_watch.hpp"
#include "fast_pass.hpp"
#include "segment_log.hpp"

namespace ecpair::sim {

namespace {

using detail::segment_log;

PortMask port_mask(const Esc& esc) {
    PortMask mask = 0;
    for (int p = 0; p < kPortCount; ++p) {
        if (esc.port_implemented(p)) mask = static_cast<PortMask>(mask | port_bit(p));
    }
    return mask;
}

// "A, B" for a two-port slave.
std::string implemented_port_letters(const Esc& esc) {
    std::string letters;
    for (int p = 0; p < kPortCount; ++p) {
        if (!esc.port_implemented(p)) continue;
        if (!letters.empty()) letters += ", ";
        letters += port_letter(p);
    }
    return letters;
}

std::vector<PortMask> port_masks(const std::vector<Esc>& escs) {
    std::vector<PortMask> masks;
    masks.reserve(escs.size());
    for (const auto& esc : escs) masks.push_back(port_mask(esc));
    return masks;
}

std::vector<Esc> make_escs(std::vector<EscDescription> descriptions) {
    std::vector<Esc> escs;
    escs.reserve(descriptions.size());
    for (auto& description : descriptions) escs.emplace_back(std::move(description));
    return escs;
}

const eni::PreviousPort* selected_previous_port(const eni::Slave& slave) {
    for (const auto& previous : slave.previous_ports) {
        if (previous.selected) return &previous;
    }
    return slave.previous_ports.empty() ? nullptr : &slave.previous_ports.front();
}

}  // namespace

EscDescription unknown_slave_description() {
    EscDescription description;
    description.name = "unknown slave";
    description.vendor_id = kUnknownSlaveVendorId;
    description.product_code = 0x00000001;
    description.revision_no = 0x00000001;
    description.physics = "YY";
    return description;
}

Segment::Segment(std::vector<Esc> escs, Topology topology, SegmentOptions options)
    : escs_(std::move(escs)),
      origins_(escs_.size()),
      topology_(std::move(topology)),
      options_(options),
      fast_(std::make_unique<detail::FastPass>()),
      dc_(std::make_unique<detail::DcWatch>()) {
    for (auto& esc : escs_) fit_hardware(esc);
    update_links(/*announce=*/false);  // the initial links are no news
}

Segment::Segment(Segment&&) noexcept = default;
Segment& Segment::operator=(Segment&&) noexcept = default;
Segment::~Segment() = default;

Expected<Segment, TopologyError> Segment::build(std::vector<SlaveSpec> specs, SegmentOptions options,
                                                const std::string& file) {
    std::vector<EscDescription> descriptions;
    descriptions.reserve(specs.size());
    for (auto& spec : specs) descriptions.push_back(std::move(spec.esc));
    auto escs = make_escs(std::move(descriptions));
    const auto masks = port_masks(escs);

    std::vector<TopologySlave> placed;
    placed.reserve(specs.size());
    for (std::size_t i = 0; i < specs.size(); ++i) {
        placed.push_back(TopologySlave{escs[i].description().name, specs[i].phys_addr, masks[i], specs[i].previous_port,
                                       specs[i].source_line, specs[i].floating});
    }
    auto topology = Topology::from_slaves(placed);
    if (!topology) {
        TopologyError error = std::move(topology).error();
        error.file = file;
        return unexpected(std::move(error));
    }
    Segment segment(std::move(escs), std::move(topology).value(), options);
    for (std::size_t i = 0; i < specs.size(); ++i) {
        segment.origins_[i].group = specs[i].group;
        segment.group_count_ = std::max(segment.group_count_, specs[i].group);
        const bool first_of_group = specs[i].group != 0 && (i == 0 || specs[i - 1].group != specs[i].group);
        segment.origins_[i].group_head = first_of_group;
    }
    return segment;
}

Expected<Segment, TopologyError> Segment::from_eni(const eni::EniConfig& config, SegmentOptions options) {
    std::vector<SlaveSpec> specs;
    specs.reserve(config.slaves.size());
    const auto groups = eni::HotConnectGroups::of(config);
    // A slave ahead of the ENI's reference clock without a <DC> element has no
    // DC: the configurator takes the first DC-capable slave as the reference
    // (datasheet I §9.1; TwinCAT's twincat_kpierczy_5slaves.xml). Of the others
    // the ENI says nothing: they keep the ET1100's 64-bit DC.
    std::size_t reference = 0;
    while (reference < config.slaves.size() &&
           !(config.slaves[reference].dc && config.slaves[reference].dc->reference_clock)) {
        ++reference;
    }
    if (reference == config.slaves.size()) reference = 0;
    for (std::size_t i = 0; i < config.slaves.size(); ++i) {
        const auto& slave = config.slaves[i];
        const auto* previous = selected_previous_port(slave);
        EscDescription description = EscDescription::from_eni(slave);
        if (i < reference && !slave.dc) description.dc = DcSupport::None;
        specs.push_back(SlaveSpec{std::move(description), slave.info.phys_addr,
                                  previous ? std::optional<eni::PreviousPort>(*previous) : std::nullopt,
                                  slave.source_line, groups.group_of(i), eni::is_floating_head(config, i)});
    }
    return build(std::move(specs), options, config.source_path);
}

Expected<Segment, TopologyError> Segment::from_specs(std::vector<SlaveSpec> slaves, SegmentOptions options) {
    return build(std::move(slaves), options, {});
}

Expected<Segment, TopologyError> Segment::with_wiring(std::vector<EscDescription> slaves, std::vector<Cable> cables,
                                                      SegmentOptions options) {
    auto escs = make_escs(std::move(slaves));
    auto topology = Topology::from_cables(port_masks(escs), std::move(cables));
    if (!topology) return unexpected(std::move(topology).error());
    return Segment(std::move(escs), std::move(topology).value(), options);
}

// ------------------------------------------------------------------ links

bool Segment::endpoint_alive(const Endpoint& end) const {
    return end.is_side() ? side_link_[static_cast<std::size_t>(end.side)] : escs_[end.slave].powered();
}

bool Segment::side_peer_alive(Side side) const {
    const auto index = topology_.cable_at(Endpoint::of_side(side));
    if (!index) return false;
    const Cable& cable = topology_.cable(*index);
    if (!cable.intact) return false;
    const Endpoint peer = topology_.peer(*index, Endpoint::of_side(side));
    return peer.is_side() || escs_[peer.slave].powered();
}

bool Segment::cable_has_link(std::size_t index) const {
    const Cable& cable = topology_.cable(index);
    return cable.intact && endpoint_alive(cable.upstream) && endpoint_alive(cable.downstream);
}

void Segment::update_links(bool announce) {
    const auto log_level = announce ? spdlog::level::info : spdlog::level::debug;
    for (std::size_t s = 0; s < escs_.size(); ++s) {
        for (int p = 0; p < kPortCount; ++p) {
            if (!topology_.has_port(s, p)) continue;
            const auto cable = topology_.cable_at(Endpoint::of_port(s, p));
            const bool up = cable && cable_has_link(*cable);
            if (escs_[s].physical_link(p) != up) {
                escs_[s].set_physical_link(p, up);
                segment_log().log(log_level, "slave {} port {}: link {}", s + 1, p, up ? "up" : "down");
            }
        }
    }
    refresh_digests();
    dc_->rebuild(escs_);
}

void Segment::replug(std::span<const std::size_t> cables) {
    for (const std::size_t index : cables) {
        const Cable& cable = topology_.cable(index);
        for (const Endpoint* end : {&cable.upstream, &cable.downstream}) {
            if (!end->is_side() && escs_[end->slave].physical_link(end->port)) {
                escs_[end->slave].set_physical_link(end->port, false);
                segment_log().info("{}: link down (cable re-plugged)", describe(*end));
            }
        }
    }
    update_links();
}

// ------------------------------------------------------------------ faults

Expected<std::size_t, FaultError> Segment::slave_index(std::size_t position) const {
    if (escs_.empty()) return unexpected(FaultError{"the segment has no slaves"});
    if (position < 1 || position > escs_.size()) {
        return unexpected(FaultError{fmt::format("position {} is out of range 1..{}", position, escs_.size())});
    }
    return position - 1;
}

Expected<std::size_t, FaultError> Segment::cable_after(std::size_t k) const {
    if (k > escs_.size()) {
        return unexpected(FaultError{fmt::format("link {} is out of range 0..{}", k, escs_.size())});
    }
    const auto cable = topology_.cable_after(k);
    if (!cable) {
        return unexpected(FaultError{k == escs_.size() ? std::string("the RED side is not connected to any slave")
                                                       : fmt::format("slave {} has no cable on port A", k + 1)});
    }
    return *cable;
}

bool Segment::link_after_intact(std::size_t k) const {
    const auto cable = topology_.cable_after(k);
    return cable && topology_.cable(*cable).intact;
}

Expected<void, FaultError> Segment::power_off(std::size_t position) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    Esc& esc = escs_[*index];
    if (!esc.powered()) return {};
    esc.power_off();
    segment_log().info("slave {} '{}': power off", position, esc.description().name);
    update_links();
    return {};
}

Expected<void, FaultError> Segment::power_on(std::size_t position) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    Esc& esc = escs_[*index];
    if (esc.powered()) return {};
    power_on_esc(*index);
    segment_log().info("slave {} '{}': power on", position, esc.description().name);
    update_links();
    return {};
}

Expected<void, FaultError> Segment::break_link_after(std::size_t k) {
    const auto cable = cable_after(k);
    if (!cable) return unexpected(cable.error());
    if (!topology_.cable(*cable).intact) return {};
    topology_.set_intact(*cable, false);
    segment_log().info("link after slave {} ({} - {}): cut", k, describe(topology_.cable(*cable).upstream),
                       describe(topology_.cable(*cable).downstream));
    update_links();
    return {};
}

Expected<void, FaultError> Segment::repair_link_after(std::size_t k) {
    const auto cable = cable_after(k);
    if (!cable) return unexpected(cable.error());
    if (topology_.cable(*cable).intact) return {};
    topology_.set_intact(*cable, true);
    segment_log().info("link after slave {} ({} - {}): repaired", k, describe(topology_.cable(*cable).upstream),
                       describe(topology_.cable(*cable).downstream));
    update_links();
    return {};
}

void Segment::set_side_link(Side side, bool up) {
    bool& link = side_link_[static_cast<std::size_t>(side)];
    if (link == up) return;
    link = up;
    segment_log().info("{} side: carrier {}", to_string(side), up ? "up" : "down");
    update_links();
}

Expected<void, FaultError> Segment::insert_unknown_slave(std::size_t position) {
    if (position < 1 || position > escs_.size() + 1) {
        return unexpected(FaultError{fmt::format("position {} is out of range 1..{}", position, escs_.size() + 1)});
    }
    const std::size_t index = position - 1;
    Esc esc(unknown_slave_description());
    fit_hardware(esc);
    if (auto inserted = topology_.insert_slave(index, port_mask(esc)); !inserted) {
        return unexpected(FaultError{inserted.error().message});
    }
    escs_.insert(escs_.begin() + static_cast<std::ptrdiff_t>(index), std::move(esc));
    origins_.insert(origins_.begin() + static_cast<std::ptrdiff_t>(index), Origin{true, 0, false});
    segment_log().info("unknown slave (vendor {:#010x}) inserted as slave {}", kUnknownSlaveVendorId, position);

    const std::array<std::size_t, 2> replugged{*topology_.cable_at(Endpoint::of_port(index, 0)),
                                               *topology_.cable_at(Endpoint::of_port(index, 1))};
    replug(replugged);
    return {};
}

Expected<void, FaultError> Segment::remove_unknown_slave(std::size_t position) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    if (!origins_[*index].added) {
        return unexpected(
            FaultError{fmt::format("slave {} is '{}' from the ENI; only slaves added by insert-unknown, "
                                   "plug-unknown or plug-duplicate can be removed",
                                   position, escs_[*index].description().name)});
    }
    // Where the slave's upstream cable came from: after the removal that end
    // is plugged into the slave's old downstream neighbour.
    std::optional<Endpoint> upstream;
    if (const auto in = topology_.cable_at(Endpoint::of_port(*index, 0))) {
        upstream = topology_.peer(*in, Endpoint::of_port(*index, 0));
        if (!upstream->is_side() && upstream->slave > *index) --upstream->slave;
    }
    if (auto removed = topology_.remove_slave(*index); !removed) {
        return unexpected(FaultError{removed.error().message});
    }
    for (int p = 0; p < kPortCount; ++p) rx_errors_pending_ -= escs_[*index].rx_errors_pending(p);
    escs_.erase(escs_.begin() + static_cast<std::ptrdiff_t>(*index));
    origins_.erase(origins_.begin() + static_cast<std::ptrdiff_t>(*index));
    segment_log().info("unknown slave {} removed", position);

    if (upstream) {
        if (const auto joined = topology_.cable_at(*upstream)) {
            const std::array<std::size_t, 1> replugged{*joined};
            replug(replugged);
            return {};
        }
    }
    update_links();
    return {};
}

Expected<void, FaultError> Segment::inject_rx_errors(std::size_t position, int port, std::uint32_t frames) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    Esc& esc = escs_[*index];
    if (!esc.port_implemented(port)) {
        return unexpected(FaultError{fmt::format("slave {} '{}' has no port {} (its ports: {})", position,
                                                 esc.description().name, port_letter(port),
                                                 implemented_port_letters(esc))});
    }
    const std::uint32_t before = esc.rx_errors_pending(port);
    esc.inject_rx_errors(port, frames);
    rx_errors_pending_ += esc.rx_errors_pending(port) - before;
    segment_log().info("slave {} '{}' port {}: the next {} frame(s) arriving there are damaged", position,
                       esc.description().name, port_letter(port), esc.rx_errors_pending(port));
    return {};
}

Expected<void, FaultError> Segment::set_eeprom_alias(std::size_t position, std::uint16_t alias) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].set_eeprom_alias(alias);
    segment_log().info("slave {}: EEPROM alias set to {}", position, alias);
    return {};
}

Expected<void, FaultError> Segment::set_id_selector(std::size_t position, std::uint16_t value) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].set_id_selector(value);
    segment_log().info("slave {}: ID selector set to {}", position, value);
    return {};
}

Expected<void, FaultError> Segment::send_emergency(std::size_t position, const wire::CoeEmergency& emergency) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    if (auto sent = escs_[*index].send_emergency(emergency); !sent) {
        return unexpected(FaultError{fmt::format("slave {} sends no emergency: {}", position, sent.error())});
    }
    refresh_digest(*index);  // SM1 is full now: an event for the IRQ field
    segment_log().info("slave {}: CoE emergency 0x{:04x} queued", position, emergency.error_code);
    return {};
}

Expected<void, FaultError> Segment::set_foe_password(std::size_t position, std::uint32_t password) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    auto* foe = escs_[*index].foe_server();
    if (foe == nullptr) return unexpected(FaultError{fmt::format("slave {} offers no FoE", position)});
    foe->set_password(password);
    segment_log().info("slave {}: FoE password {}", position, password == 0 ? std::string("none") : fmt::format("0x{:08x}", password));
    return {};
}

Expected<void, FaultError> Segment::set_foe_busy(std::size_t position, std::uint32_t packets) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    auto* foe = escs_[*index].foe_server();
    if (foe == nullptr) return unexpected(FaultError{fmt::format("slave {} offers no FoE", position)});
    foe->set_busy_packets(packets);
    segment_log().info("slave {}: FoE busy for the next {} data packet(s)", position, packets);
    return {};
}

}  // namespace ecpair::sim
