// The DC plan from the ENI (see the header for the rules and checks).

#include "ecpair/dc/dc_plan.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::dc {
namespace {

bool is_write(wire::Command c) {
    return c == wire::Command::Apwr || c == wire::Command::Fpwr || c == wire::Command::Bwr;
}

// Whether a register write of `cmd` covers `address`, and the byte it writes there.
std::optional<std::uint8_t> written_byte(const eni::EcatCmd& cmd, std::uint16_t address) {
    if (!is_write(cmd.command) || address < cmd.ado || address >= cmd.ado + cmd.data.size()) return std::nullopt;
    return cmd.data[address - cmd.ado];
}

// DC mode switched on by the slave's own InitCmds (no <DC> element): the
// activation, and the SYNC0 cycle time they write.
std::optional<DcSlave> from_init_cmds(const eni::Slave& slave, std::size_t index) {
    std::optional<DcSlave> found;
    std::uint32_t cycle0 = 0;
    std::uint32_t cycle1 = 0;
    for (const auto& cmd : slave.init_cmds) {
        if (cmd.command == wire::Command::Bwr) continue;  // the master's clearing, copied into a slave's list
        const auto activation = written_byte(cmd, wire::reg::kDcActivation);
        if (activation && (*activation & 0x01) != 0 && !found) {
            found = DcSlave{index, 0, 0, 0, cmd.source_line};
        }
        if (is_write(cmd.command) && cmd.ado == wire::reg::kDcCycleTime0 && cmd.data.size() >= 4) {
            cycle0 = load_le<std::uint32_t>(cmd.data, 0);
            if (cmd.data.size() >= 8) cycle1 = load_le<std::uint32_t>(cmd.data, 4);
        }
    }
    if (found) {
        found->sync0_cycle_ns = cycle0;
        found->sync1_cycle_ns = cycle1;
    }
    return found;
}

std::string slave_label(const eni::EniConfig& eni, std::size_t index) {
    const auto& s = eni.slaves[index];
    return fmt::format("slave '{}' (station {})", s.info.name, s.info.phys_addr);
}

}  // namespace

std::vector<std::size_t> reference_candidates(const eni::EniConfig& eni) {
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        const auto& dc = eni.slaves[i].dc;
        if (dc && dc->reference_clock) {
            candidates.push_back(i);
            break;
        }
    }
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        if (eni.slaves[i].dc && (candidates.empty() || candidates.front() != i)) candidates.push_back(i);
    }
    if (candidates.empty()) {
        for (std::size_t i = 0; i < eni.slaves.size(); ++i) candidates.push_back(i);
    }
    return candidates;
}

const DcSlave* DcPlan::slave(std::size_t index) const {
    const auto found =
        std::find_if(slaves_.begin(), slaves_.end(), [index](const DcSlave& s) { return s.index == index; });
    return found == slaves_.end() ? nullptr : &*found;
}

std::optional<std::size_t> DcPlan::reference(const std::vector<bool>& present) const {
    for (const auto candidate : candidates_) {
        if (candidate < present.size() && present[candidate]) return candidate;
    }
    return std::nullopt;
}

Expected<DcPlan, std::string> DcPlan::build(const eni::EniConfig& eni, std::chrono::nanoseconds cycle_time) {
    DcPlan plan;
    plan.cycle_time_ = cycle_time;
    const auto where = [&eni](int line) { return fmt::format("{}:{}", eni.source_path, line); };

    plan.candidates_ = dc::reference_candidates(eni);

    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        const auto& s = eni.slaves[i];
        std::optional<DcSlave> dc_mode;
        if (s.dc && s.dc->cycle_time0_ns.value_or(0) != 0) {
            dc_mode = DcSlave{i, *s.dc->cycle_time0_ns, s.dc->cycle_time1_ns.value_or(0),
                              s.dc->shift_time_ns.value_or(0), s.source_line};
        } else {
            dc_mode = from_init_cmds(s, i);
        }
        if (!dc_mode) continue;
        const auto cycle = static_cast<std::uint64_t>(cycle_time.count());
        if (dc_mode->sync0_cycle_ns != 0 && cycle != 0 && cycle % dc_mode->sync0_cycle_ns != 0) {
            return unexpected(
                fmt::format("{}: {} runs in DC mode with a SYNC0 cycle time of {} ns, but the bus cycle "
                            "time {} ns is not a whole multiple of it: SYNC0 would slide against the "
                            "frames",
                            where(dc_mode->source_line), slave_label(eni, i), dc_mode->sync0_cycle_ns, cycle));
        }
        plan.slaves_.push_back(*dc_mode);
    }
    if (!plan.used()) return plan;

    // The reference must come before every slave in DC mode: the ARMW
    // distributes its time only to the slaves after it.
    const auto& first = plan.slaves_.front();
    const auto reference = plan.candidates_.front();
    if (first.index < reference) {
        return unexpected(
            fmt::format("{}: {} runs in DC mode but comes before the reference clock {} in ring order: "
                        "the drift compensation (ARMW on 0x0910) would give it the master's bytes "
                        "instead of the reference's time",
                        where(first.source_line), slave_label(eni, first.index), slave_label(eni, reference)));
    }
    return plan;
}

}  // namespace ecpair::dc
