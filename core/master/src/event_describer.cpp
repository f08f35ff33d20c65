// The texts follow one pattern: what happened, to which frame / slave, and
// what the master did about it. Slaves are named as the ENI names them,
// with the 1-based ring position operators count and the station address.
// A summary reads "N more in the last 1.0 s (cycles F-L; T since cycle S)"
// followed by each subject's latest event and its count.

#include "ecpair/master/event_describer.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::master {
namespace {

std::uint16_t adp_of(std::uint32_t address) { return static_cast<std::uint16_t>(address & 0xFFFF); }
std::uint16_t ado_of(std::uint32_t address) { return static_cast<std::uint16_t>(address >> 16); }

bool writes_fmmu(const eni::EcatCmd& cmd) {
    return (cmd.command == wire::Command::Fpwr || cmd.command == wire::Command::Apwr) && cmd.ado >= wire::reg::kFmmuBase &&
           cmd.ado < wire::reg::kSmBase && cmd.data.size() >= wire::FmmuConfig::kSize;
}

std::string seconds_text(std::chrono::nanoseconds span) {
    return fmt::format("{:.1f} s", std::chrono::duration<double>(span).count());
}

}  // namespace

EventDescriber::EventDescriber(std::shared_ptr<const eni::EniConfig> eni, const CyclicPlan* plan)
    : eni_(std::move(eni)), plan_(plan) {}

std::string EventDescriber::describe(const Event& e) const {
    return fmt::format("cycle {}: {}", e.cycle, e.kind.type().describe(e, *this));
}

std::string EventDescriber::subjects_text(const EventReport& report) const {
    std::vector<std::string> parts;
    parts.reserve(report.subjects.size() + 1);
    for (const SubjectCount& s : report.subjects) {
        parts.push_back(fmt::format("{} x {}", s.count, s.last.kind.type().describe(s.last, *this)));
    }
    if (report.other > 0) parts.push_back(fmt::format("{} of other subjects", report.other));
    return fmt::format("{}", fmt::join(parts, " | "));
}

std::string EventDescriber::describe(const EventReport& report) const {
    switch (report.repetition) {
        case Repetition::Single: break;
        case Repetition::Summary:
            return fmt::format("cycle {}: {} more in the last {} (cycles {}-{}; {} since cycle {}, still going on): {}",
                               report.event.cycle, report.count, seconds_text(report.span), report.first_cycle,
                               report.last_cycle, report.total, report.start_cycle, subjects_text(report));
        case Repetition::End:
            return fmt::format("cycle {}: ended, none since cycle {}: {} in {} (cycles {}-{}), {} of them since the "
                               "last report: {}",
                               report.event.cycle, report.last_cycle, report.total, seconds_text(report.span),
                               report.start_cycle, report.last_cycle, report.count, subjects_text(report));
    }
    return describe(report.event);
}

std::string EventDescriber::slave(std::size_t index) const {
    if (!eni_ || index >= eni_->slaves.size()) return fmt::format("#{} (not in the ENI)", index + 1);
    const auto& info = eni_->slaves[index].info;
    return fmt::format("'{}' (position {}, station {})", info.name, info.ring_position + 1, info.phys_addr);
}

std::string EventDescriber::slave_at_position(std::uint32_t position) const {
    if (eni_) {
        for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
            if (eni_->slaves[i].info.ring_position + 1u == position) return slave(i);
        }
    }
    return fmt::format("position {}", position);
}

std::size_t EventDescriber::slave_count() const { return eni_ ? eni_->slaves.size() : 0; }

std::string EventDescriber::datagram(const PlannedDatagram& d) const {
    std::string text;
    if (wire::addressing_of(d.command) == wire::Addressing::Logical) {
        text = fmt::format("{} 0x{:08x}, {} bytes", wire::to_string(d.command), d.address, d.length);
    } else {
        text = fmt::format("{} 0x{:04x}, {} bytes", wire::to_string(d.command), ado_of(d.address), d.length);
    }
    if (!d.comment.empty()) text += fmt::format(", '{}'", d.comment);
    if (d.source_line > 0) text += fmt::format(", ENI line {}", d.source_line);
    return text;
}

std::string EventDescriber::cyclic_frame(std::uint32_t index, std::uint8_t state) const {
    if (plan_ == nullptr || index >= plan_->frames.size()) {
        return fmt::format("cyclic frame {} ({})", index + 1, wire::al_state_name(state));
    }
    std::vector<std::string> parts;
    const auto slave_state = static_cast<eni::SlaveState>(state);
    for (const auto& d : plan_->frames[index].datagrams) {
        if (!d.states.contains(slave_state)) continue;
        parts.push_back(wire::addressing_of(d.command) == wire::Addressing::Logical
                            ? fmt::format("{} 0x{:08x} {} B", wire::to_string(d.command), d.address, d.length)
                            : fmt::format("{} 0x{:04x}", wire::to_string(d.command), ado_of(d.address)));
    }
    return fmt::format("cyclic frame {} of {} ({}: {})", index + 1, plan_->frames.size(), wire::al_state_name(state),
                       parts.empty() ? std::string("no datagram") : fmt::format("{}", fmt::join(parts, ", ")));
}

const PlannedDatagram* EventDescriber::cyclic_datagram(std::uint32_t frame, std::uint32_t datagram) const {
    if (plan_ == nullptr || frame >= plan_->frames.size() || datagram >= plan_->frames[frame].datagrams.size()) {
        return nullptr;
    }
    return &plan_->frames[frame].datagrams[datagram];
}

std::string EventDescriber::slaves_mapping(std::uint32_t logical, std::size_t length) const {
    if (!eni_) return {};
    std::vector<std::string> names;
    for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
        const bool maps = std::any_of(eni_->slaves[i].init_cmds.begin(), eni_->slaves[i].init_cmds.end(),
                                      [&](const eni::EcatCmd& cmd) {
                                          return writes_fmmu(cmd) &&
                                                 wire::FmmuConfig::decode(cmd.data).overlaps(logical, length);
                                      });
        if (maps) names.push_back(slave(i));
    }
    if (names.empty()) return {};
    return fmt::format("; the slaves mapping it: {}", fmt::join(names, ", "));
}

std::string EventDescriber::addressed_station(std::uint16_t station) const {
    std::string who;
    if (eni_) {
        for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
            if (eni_->slaves[i].info.phys_addr == station) who = "; addressed to " + slave(i);
        }
    }
    return who;
}

std::string EventDescriber::acyclic_target(wire::Command command, std::uint32_t address) const {
    switch (wire::addressing_of(command)) {
        case wire::Addressing::Logical: return fmt::format("logical 0x{:08x}", address);
        case wire::Addressing::Broadcast: return fmt::format("all slaves, register 0x{:04x}", ado_of(address));
        case wire::Addressing::AutoIncrement: {
            const std::uint32_t position = (0x10000u - adp_of(address)) % 0x10000u + 1u;
            return fmt::format("{}, register 0x{:04x}", slave_at_position(position), ado_of(address));
        }
        case wire::Addressing::Configured:
            if (eni_) {
                for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
                    if (eni_->slaves[i].info.phys_addr == adp_of(address)) {
                        return fmt::format("{}, register 0x{:04x}", slave(i), ado_of(address));
                    }
                }
            }
            return fmt::format("station {}, register 0x{:04x}", adp_of(address), ado_of(address));
        default: break;
    }
    return fmt::format("0x{:08x}", address);
}

}  // namespace ecpair::master
