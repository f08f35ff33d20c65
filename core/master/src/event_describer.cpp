// The texts follow one pattern: what happened, to which frame / slave, and
// what the master did about it. Slaves are named as the ENI names them,
// with the 1-based ring position operators count and the station address.

#include "ecpair/master/event_describer.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/master/frame_tracker.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::master {
namespace {

std::string state_name(std::uint32_t state) { return wire::al_state_name(static_cast<std::uint8_t>(state)); }

std::uint16_t adp_of(std::uint32_t address) { return static_cast<std::uint16_t>(address & 0xFFFF); }
std::uint16_t ado_of(std::uint32_t address) { return static_cast<std::uint16_t>(address >> 16); }

bool writes_fmmu(const eni::EcatCmd& cmd) {
    return (cmd.command == wire::Command::Fpwr || cmd.command == wire::Command::Apwr) && cmd.ado >= wire::reg::kFmmuBase &&
           cmd.ado < wire::reg::kSmBase && cmd.data.size() >= wire::FmmuConfig::kSize;
}

}  // namespace

EventDescriber::EventDescriber(std::shared_ptr<const eni::EniConfig> eni, const CyclicPlan* plan)
    : eni_(std::move(eni)), plan_(plan) {}

std::string EventDescriber::slave(std::size_t index) const {
    if (!eni_ || index >= eni_->slaves.size()) return fmt::format("slave #{} (not in the ENI)", index + 1);
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
    if (plan_ == nullptr || index >= plan_->frames.size()) return fmt::format("cyclic frame {}", index + 1);
    std::vector<std::string> parts;
    const auto slave_state = static_cast<eni::SlaveState>(state);
    for (const auto& d : plan_->frames[index].datagrams) {
        if (!d.states.contains(slave_state)) continue;
        parts.push_back(wire::addressing_of(d.command) == wire::Addressing::Logical
                            ? fmt::format("{} 0x{:08x} {} B", wire::to_string(d.command), d.address, d.length)
                            : fmt::format("{} 0x{:04x}", wire::to_string(d.command), ado_of(d.address)));
    }
    return fmt::format("cyclic frame {} of {} ({}: {})", index + 1, plan_->frames.size(), state_name(state),
                       parts.empty() ? std::string("no datagram") : fmt::format("{}", fmt::join(parts, ", ")));
}

// Slaves whose FMMU InitCmds map part of the logical range.
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

std::string EventDescriber::wkc_error(const Event& e) const {
    const auto prefix = fmt::format("cycle {}: ", e.cycle);
    const auto what = fmt::format("WKC {}, expected {}", e.d, e.c);
    if (plan_ == nullptr || e.a >= plan_->frames.size() || e.b >= plan_->frames[e.a].datagrams.size()) {
        return prefix + fmt::format("cyclic frame {} datagram {} came back with {}: the cycle's inputs are marked invalid",
                                    e.a + 1, e.b + 1, what);
    }
    const PlannedDatagram& d = plan_->frames[e.a].datagrams[e.b];
    std::string who;
    switch (wire::addressing_of(d.command)) {
        case wire::Addressing::Logical: who = slaves_mapping(d.address, d.length); break;
        case wire::Addressing::Broadcast:
            if (e.d < e.c) who = fmt::format("; {} of the {} slaves did not answer", e.c - e.d, e.c);
            break;
        case wire::Addressing::Configured:
            if (eni_) {
                for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
                    if (eni_->slaves[i].info.phys_addr == adp_of(d.address)) who = "; addressed to " + slave(i);
                }
            }
            break;
        default: break;
    }
    return prefix + fmt::format("cyclic frame {} datagram {} ({}) came back with {}{}: the cycle's inputs are marked "
                                "invalid",
                                e.a + 1, e.b + 1, datagram(d), what, who);
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

std::string EventDescriber::lost_frame(const Event& e) const {
    const auto prefix = fmt::format("cycle {}: ", e.cycle);
    const auto d = LostFrameDetail::decode(e);
    switch (static_cast<FrameKind>(e.a)) {
        case FrameKind::Cyclic:
            return prefix + fmt::format("{} lost ({}): this cycle's inputs keep their last values",
                                        cyclic_frame(e.b, d.master_state), d.copies_text());
        case FrameKind::Acyclic: {
            const std::string more = d.datagrams > 1 ? fmt::format(" and {} more datagram(s)", d.datagrams - 1) : "";
            return prefix + fmt::format("acyclic frame lost: {} to {}, {} bytes{} ({}): its requests are sent again "
                                        "until their timeout",
                                        wire::to_string(d.first_command), acyclic_target(d.first_command, d.first_address),
                                        d.first_length, more, d.copies_text());
        }
        case FrameKind::MasterRed: break;
    }
    return master::describe(e);
}

std::string EventDescriber::describe(const Event& e) const {
    const auto prefix = fmt::format("cycle {}: ", e.cycle);
    const std::size_t slave_count = eni_ ? eni_->slaves.size() : 0;
    switch (e.kind) {
        case EventKind::CyclicWkcError: return wkc_error(e);
        case EventKind::FrameLost: return lost_frame(e);
        case EventKind::LineBreak:
            if (e.b == 0) break;
            if (e.a == 0) return prefix + "line break at the MAIN cable: every slave is reached from RED";
            if (e.a >= slave_count) {
                return prefix + fmt::format("line break after slave {} {}, at the RED cable: every slave is reached "
                                            "from MAIN",
                                            e.a, slave_at_position(e.a));
            }
            return prefix + fmt::format("line break after slave {} {}, before {}: slaves 1-{} are reached from MAIN, "
                                        "{}-{} from RED; every slave stays in the cycle",
                                        e.a, slave_at_position(e.a), slave_at_position(e.a + 1), e.a, e.a + 1, slave_count);
        case EventKind::SlavePresence:
            return prefix + fmt::format("slave {} is {}", slave(e.a),
                                        e.b != 0 ? "present" : "absent (no answer at its station address)");
        case EventKind::SlaveStateError:
            return prefix + fmt::format("slave {} is in {}, AL status code 0x{:04x} ({})", slave(e.a),
                                        wire::AlStatus{static_cast<std::uint8_t>(e.b)}.to_string(), e.c,
                                        wire::al_status_code_text(static_cast<std::uint16_t>(e.c)));
        case EventKind::TransitionFailed:
            if (e.c == 0xFFFF) break;
            return prefix + fmt::format("transition {} -> {} failed at slave {}: the master stays in {}",
                                        state_name(e.a), state_name(e.b), slave(e.c), state_name(e.a));
        case EventKind::BusMismatch:
            return prefix + fmt::format("bus mismatch at position {} (configured there: {})", e.a + 1,
                                        slave_at_position(e.a + 1));
        case EventKind::CoeEmergency: return prefix + fmt::format("slave {}: {}", slave(e.a), coe_emergency_text(e));
        default: break;
    }
    return master::describe(e);
}

}  // namespace ecpair::master
