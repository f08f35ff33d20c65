// The Hot-Connect faults of a segment: a group's power, plugging a group
// (floating or not) into another port, slaves plugged into free ports (an
// unknown one, a duplicate of a configured one), a slave that refuses
// states, the ETG.1020 legacy ID selector. Every re-plug takes the link away
// from the ends of the cables it touches first, as a real cable does.

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/sim/segment.hpp"
#include "segment_log.hpp"

namespace ecpair::sim {
namespace {

using detail::segment_log;

Expected<void, FaultError> check_port(int port) {
    if (port < 0 || port >= kPortCount) {
        return unexpected(FaultError{fmt::format("port {} is not one of A..D (0..3)", port)});
    }
    return {};
}

}  // namespace

Expected<std::size_t, FaultError> Segment::group_head(std::size_t group) const {
    if (group == 0 || group > group_count_) {
        return unexpected(FaultError{group_count_ == 0
                                         ? std::string("the ENI has no Hot-Connect groups")
                                         : fmt::format("group {} is out of range 1..{}", group, group_count_)});
    }
    for (std::size_t i = 0; i < origins_.size(); ++i) {
        if (origins_[i].group == group && origins_[i].group_head) return i;
    }
    return unexpected(FaultError{fmt::format("group {} has no head on this segment", group)});
}

Expected<void, FaultError> Segment::set_group_power(std::size_t group, bool on) {
    if (auto head = group_head(group); !head) return unexpected(head.error());
    std::size_t count = 0;
    for (std::size_t i = 0; i < escs_.size(); ++i) {
        if (origins_[i].group != group) continue;
        ++count;
        if (on) {
            power_on_esc(i);
        } else {
            escs_[i].power_off();
        }
    }
    segment_log().info("group {}: power {} ({} slave(s))", group, on ? "on" : "off", count);
    update_links();
    return {};
}

Expected<void, FaultError> Segment::plug_group(std::size_t group, std::size_t position, int port) {
    const auto head = group_head(group);
    if (!head) return unexpected(head.error());
    const auto target = slave_index(position);
    if (!target) return unexpected(target.error());
    if (auto ok = check_port(port); !ok) return ok;
    std::vector<std::size_t> touched;
    if (topology_.cable_at(Endpoint::of_port(*head, 0))) {
        const auto was = topology_.unplug(*head);
        segment_log().info("group {}: unplugged from {}", group, describe(*was));
    }
    if (auto plugged = topology_.plug(Endpoint::of_port(*target, port), *head); !plugged) {
        update_links();
        return unexpected(FaultError{plugged.error().message});
    }
    segment_log().info("group {}: head '{}' plugged into slave {} port {}", group, escs_[*head].description().name,
                       position, port_letter(port));
    touched.push_back(*topology_.cable_at(Endpoint::of_port(*head, 0)));
    replug(touched);
    return {};
}

Expected<void, FaultError> Segment::unplug_group(std::size_t group) {
    const auto head = group_head(group);
    if (!head) return unexpected(head.error());
    const auto was = topology_.unplug(*head);
    if (!was) return unexpected(FaultError{was.error().message});
    segment_log().info("group {}: unplugged from {}", group, describe(*was));
    update_links();
    return {};
}

Expected<void, FaultError> Segment::plug_added(Esc esc, std::size_t position, int port, std::string_view what) {
    const auto target = slave_index(position);
    if (!target) return unexpected(target.error());
    if (auto ok = check_port(port); !ok) return ok;
    PortMask ports = 0;
    for (int p = 0; p < kPortCount; ++p) {
        if (esc.port_implemented(p)) ports = static_cast<PortMask>(ports | port_bit(p));
    }
    if (auto attached = topology_.attach_slave(ports, Endpoint::of_port(*target, port)); !attached) {
        return unexpected(FaultError{attached.error().message});
    }
    fit_hardware(esc);
    escs_.push_back(std::move(esc));
    origins_.push_back(Origin{true, 0, false});
    segment_log().info("{} plugged into slave {} port {}: it is slave {}", what, position, port_letter(port), escs_.size());
    const std::array<std::size_t, 1> touched{*topology_.cable_at(Endpoint::of_port(escs_.size() - 1, 0))};
    replug(touched);
    return {};
}

Expected<void, FaultError> Segment::plug_unknown_slave(std::size_t position, int port) {
    return plug_added(Esc(unknown_slave_description()), position, port,
                      fmt::format("unknown slave (vendor {:#010x})", kUnknownSlaveVendorId));
}

Expected<void, FaultError> Segment::plug_duplicate(std::size_t source, std::size_t position, int port) {
    const auto index = slave_index(source);
    if (!index) return unexpected(index.error());
    EscDescription copy = escs_[*index].description();
    copy.name += " (duplicate)";
    return plug_added(Esc(std::move(copy)), position, port, fmt::format("a duplicate of slave {}", source));
}

Expected<void, FaultError> Segment::refuse_states_from(std::size_t position, std::optional<eni::SlaveState> state) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].refuse_states_from(state);
    return {};
}

Expected<void, FaultError> Segment::set_legacy_id_selector(std::size_t position, std::uint16_t value) {
    const auto index = slave_index(position);
    if (!index) return unexpected(index.error());
    escs_[*index].set_legacy_id_selector(value);
    segment_log().info("slave {}: ETG.1020 ID selector set to {} (read at its next power-on)", position, value);
    return {};
}

}  // namespace ecpair::sim
