// Master states, the transition function, and the ordering of one
// transition's commands (see the header).

#include "ecpair/sequencer/transition_plan.hpp"

#include <algorithm>
#include <numeric>

#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/sequencer/synthesized_init_cmds.hpp"

namespace ecpair::sequencer {
namespace {

int rank(MasterState s) { return static_cast<int>(s); }

bool any_slave_has(const eni::EniConfig& eni, eni::Transition t) {
    return std::any_of(eni.slaves.begin(), eni.slaves.end(), [t](const eni::Slave& s) {
        return std::any_of(s.init_cmds.begin(), s.init_cmds.end(),
                           [t](const eni::EcatCmd& c) { return c.transitions.contains(t); });
    });
}

bool no_slave_has_esc_init_cmds(const eni::EniConfig& eni) {
    return std::all_of(eni.slaves.begin(), eni.slaves.end(), [](const eni::Slave& s) { return s.init_cmds.empty(); });
}

std::optional<eni::Transition> downward(MasterState from, MasterState to) {
    using T = eni::Transition;
    using M = MasterState;
    if (from == M::Op && to == M::Safeop) return T::OS;
    if (from == M::Op && to == M::Preop) return T::OP;
    if (from == M::Op && to == M::Init) return T::OI;
    if (from == M::Safeop && to == M::Preop) return T::SP;
    if (from == M::Safeop && to == M::Init) return T::SI;
    if (from == M::Preop && to == M::Init) return T::PI;
    return std::nullopt;
}

// Whether a slave's ESC command is the AL control write that requests the transition's target state.
bool requests_target(const eni::EcatCmd& cmd, eni::Transition t) {
    const auto state = requested_al_state(cmd);
    return state && *state == static_cast<std::uint8_t>(eni::to_state(t));
}

SlavePlan plan_slave(const eni::Slave& slave, std::size_t index, eni::Transition t) {
    SlavePlan plan;
    plan.slave_index = index;
    plan.synthesized = slave.init_cmds.empty();
    std::vector<eni::EcatCmd> esc;
    if (plan.synthesized) {
        esc = synthesize_esc_init_cmds(slave, t);
    } else {
        for (const auto& cmd : slave.init_cmds) {
            if (cmd.transitions.contains(t)) esc.push_back(cmd);
        }
    }
    // The mailbox InitCmds: CoE, then SoE, then EoE, each in ENI order.
    std::vector<SlaveStep> mailbox;
    if (slave.mailbox) {
        const auto take = [&mailbox, t](const auto& cmds) {
            for (const auto& cmd : cmds) {
                if (cmd.transitions.contains(t) && !cmd.disabled) mailbox.emplace_back(cmd);
            }
        };
        take(slave.mailbox->coe_init_cmds);
        take(slave.mailbox->soe_init_cmds);
        take(slave.mailbox->eoe_init_cmds);
    }
    const auto split = t == eni::Transition::IP
                           ? esc.end()
                           : std::find_if(esc.begin(), esc.end(),
                                          [t](const eni::EcatCmd& c) { return requests_target(c, t); });
    for (auto it = esc.begin(); it != split; ++it) plan.steps.emplace_back(std::move(*it));
    for (auto& step : mailbox) plan.steps.push_back(std::move(step));
    for (auto it = split; it != esc.end(); ++it) plan.steps.emplace_back(std::move(*it));
    return plan;
}

}  // namespace

std::string_view to_string(MasterState state) {
    switch (state) {
        case MasterState::Init: return "INIT";
        case MasterState::Preop: return "PREOP";
        case MasterState::Safeop: return "SAFEOP";
        case MasterState::Op: return "OP";
    }
    return "?";
}

eni::SlaveState to_slave_state(MasterState state) {
    switch (state) {
        case MasterState::Init: return eni::SlaveState::Init;
        case MasterState::Preop: return eni::SlaveState::Preop;
        case MasterState::Safeop: return eni::SlaveState::Safeop;
        case MasterState::Op: return eni::SlaveState::Op;
    }
    return eni::SlaveState::Init;
}

std::optional<MasterState> to_master_state(eni::SlaveState state) {
    switch (state) {
        case eni::SlaveState::Init: return MasterState::Init;
        case eni::SlaveState::Preop: return MasterState::Preop;
        case eni::SlaveState::Safeop: return MasterState::Safeop;
        case eni::SlaveState::Op: return MasterState::Op;
        case eni::SlaveState::Boot: return std::nullopt;
    }
    return std::nullopt;
}

std::optional<MasterState> transition_source(eni::Transition t) { return to_master_state(eni::from_state(t)); }
std::optional<MasterState> transition_target(eni::Transition t) { return to_master_state(eni::to_state(t)); }

std::optional<eni::Transition> next_transition(MasterState current, MasterState target, const eni::EniConfig& eni) {
    if (current == target) return std::nullopt;
    if (rank(target) > rank(current)) {
        switch (current) {
            case MasterState::Init: return eni::Transition::IP;
            case MasterState::Preop: return eni::Transition::PS;
            default: return eni::Transition::SO;
        }
    }
    const auto direct = downward(current, target);
    if (direct && (any_slave_has(eni, *direct) || no_slave_has_esc_init_cmds(eni))) return direct;
    return downward(current, static_cast<MasterState>(rank(current) - 1));
}

std::vector<std::size_t> ring_order(const eni::EniConfig& eni) {
    std::vector<std::size_t> order(eni.slaves.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&eni](std::size_t a, std::size_t b) {
        return eni.slaves[a].info.ring_position < eni.slaves[b].info.ring_position;
    });
    return order;
}

TransitionPlan plan_transition(const eni::EniConfig& eni, eni::Transition transition, const std::vector<bool>& present) {
    TransitionPlan plan;
    plan.transition = transition;
    for (const auto& cmd : eni.master.init_cmds) {
        if (!cmd.transitions.contains(transition)) continue;
        (cmd.before_slave ? plan.master_before : plan.master_after).push_back(cmd);
    }
    for (const auto index : ring_order(eni)) {
        if (index < present.size() && present[index]) plan.slaves.push_back(plan_slave(eni.slaves[index], index, transition));
    }
    return plan;
}

}  // namespace ecpair::sequencer
