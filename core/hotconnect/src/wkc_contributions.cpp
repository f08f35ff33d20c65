#include "ecpair/hotconnect/wkc_contributions.hpp"

#include <algorithm>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/command.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::hotconnect {
namespace {

struct Directions {
    bool reads = false;
    bool writes = false;
};

// Whether the slave's FMMU InitCmds map [address, address + length) for reading / writing.
Directions fmmu_directions_of(const eni::Slave& slave, std::uint32_t address, std::size_t length) {
    Directions d;
    for (const auto& cmd : slave.init_cmds) {
        if (cmd.command != wire::Command::Fpwr && cmd.command != wire::Command::Apwr) continue;
        if (cmd.ado < wire::reg::kFmmuBase || cmd.ado >= wire::reg::kSmBase) continue;
        const std::uint32_t end = static_cast<std::uint32_t>(cmd.ado) + static_cast<std::uint32_t>(cmd.data.size());
        for (std::uint32_t at = cmd.ado; at + wire::FmmuConfig::kSize <= end; at += wire::FmmuConfig::kSize) {
            if ((at - wire::reg::kFmmuBase) % wire::FmmuConfig::kSize != 0) break;
            const auto fmmu = wire::FmmuConfig::decode(ConstBytes(cmd.data).subspan(at - cmd.ado, wire::FmmuConfig::kSize));
            if (!fmmu.active || !fmmu.overlaps(address, length)) continue;
            d.reads = d.reads || fmmu.read;
            d.writes = d.writes || fmmu.write;
        }
    }
    return d;
}

std::uint16_t read_write_weight(wire::Command c) {
    switch (c) {
        case wire::Command::Aprw:
        case wire::Command::Fprw:
        case wire::Command::Brw:
        case wire::Command::Lrw: return 3;
        default: return 1;
    }
}

}  // namespace

WkcContributions WkcContributions::of(const eni::EniConfig& eni, const master::CyclicPlan& plan) {
    WkcContributions result;
    result.configured_ = eni.slaves.size();
    for (const auto& frame : plan.frames) {
        for (const auto& d : frame.datagrams) {
            DatagramContribution c;
            c.eni_expected = d.expected_wkc;
            const bool read_multiple_write = d.command == wire::Command::Armw || d.command == wire::Command::Frmw;
            switch (read_multiple_write ? wire::Addressing::Broadcast : wire::addressing_of(d.command)) {
                case wire::Addressing::Broadcast:
                    c.kind = ContributionKind::Broadcast;
                    c.per_slave = read_multiple_write ? 1 : read_write_weight(d.command);
                    break;
                case wire::Addressing::Logical:
                    c.kind = ContributionKind::Logical;
                    c.by_slave.assign(eni.slaves.size(), 0);
                    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
                        const auto dir = fmmu_directions_of(eni.slaves[i], d.address, d.length);
                        std::uint16_t w = 0;
                        if (d.command == wire::Command::Lrd) w = dir.reads ? 1 : 0;
                        if (d.command == wire::Command::Lwr) w = dir.writes ? 1 : 0;
                        if (d.command == wire::Command::Lrw) w = static_cast<std::uint16_t>((dir.reads ? 1 : 0) + (dir.writes ? 2 : 0));
                        c.by_slave[i] = w;
                    }
                    break;
                case wire::Addressing::AutoIncrement:
                case wire::Addressing::Configured: {
                    c.kind = ContributionKind::Addressed;
                    c.by_slave.assign(eni.slaves.size(), 0);
                    const auto adp = static_cast<std::uint16_t>(d.address & 0xFFFF);
                    const bool station = wire::addressing_of(d.command) == wire::Addressing::Configured;
                    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
                        const auto& info = eni.slaves[i].info;
                        if ((station && info.phys_addr == adp) || (!station && info.auto_inc_addr == adp)) {
                            c.by_slave[i] = read_write_weight(d.command);
                        }
                    }
                    break;
                }
                default: c.kind = ContributionKind::Fixed; break;
            }
            result.datagrams_.push_back(std::move(c));
        }
    }
    return result;
}

std::vector<std::optional<std::uint16_t>> WkcContributions::expected(const BusCount& bus) const {
    std::vector<std::optional<std::uint16_t>> out;
    out.reserve(datagrams_.size());
    for (const auto& d : datagrams_) {
        if (!d.eni_expected) {
            out.push_back(std::nullopt);
            continue;
        }
        int value = *d.eni_expected;
        switch (d.kind) {
            case ContributionKind::Broadcast:
                value += d.per_slave * (static_cast<int>(bus.answering) - static_cast<int>(configured_));
                break;
            case ContributionKind::Logical:
                for (std::size_t i = 0; i < d.by_slave.size(); ++i) {
                    if (i >= bus.counted.size() || !bus.counted[i]) value -= d.by_slave[i];
                }
                break;
            case ContributionKind::Addressed:
                for (std::size_t i = 0; i < d.by_slave.size(); ++i) {
                    if (i >= bus.present.size() || !bus.present[i]) value -= d.by_slave[i];
                }
                break;
            case ContributionKind::Fixed: break;
        }
        out.push_back(static_cast<std::uint16_t>(std::max(value, 0)));
    }
    return out;
}

}  // namespace ecpair::hotconnect
