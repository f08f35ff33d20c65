#pragma once
// The master's states, the transition function between them, and the plan
// of one transition: which commands run in which order.
//
// Order within a transition T (ETG.2100, docs/STATE_MACHINE.md):
//   1. master InitCmds of T with BeforeSlave;
//   2. per present slave, in ring order:
//        its ESC InitCmds of T up to (not including) the AL control write
//        that requests T's target state,
//        its mailbox InitCmds of T: CoE, then SoE, then EoE,
//        the rest of its ESC InitCmds of T (AL control, the Validate on 0x0130);
//      for IP the mailbox InitCmds come last instead: the mailbox only runs from PREOP on;
//   3. master InitCmds of T without BeforeSlave.
// A slave whose ENI entry has no ESC InitCmds at all (Advantech) gets the
// minimum made up from its ENI data (synthesized_init_cmds.hpp).
// Absent optional slaves have no part in the plan.

#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "ecpair/eni/model.hpp"

namespace ecpair::sequencer {

enum class MasterState : std::uint8_t { Init, Preop, Safeop, Op };

std::string_view to_string(MasterState state);
eni::SlaveState to_slave_state(MasterState state);
std::optional<MasterState> to_master_state(eni::SlaveState state);  // nullopt for BOOT

// The transition function: the next transition from `current` towards
// `target`, nullopt when they are equal. Up one state at a time (IP, PS, SO).
// Down: straight to the target (OS, OP, OI, SP, SI, PI) when the ENI has
// slave InitCmds for that transition or no slave has any ESC InitCmds (we
// make them up then), otherwise one state down.
std::optional<eni::Transition> next_transition(MasterState current, MasterState target, const eni::EniConfig& eni);
// The states a transition leaves and reaches (only the ones between INIT/PREOP/SAFEOP/OP).
std::optional<MasterState> transition_source(eni::Transition t);
std::optional<MasterState> transition_target(eni::Transition t);

using SlaveStep = std::variant<eni::EcatCmd, eni::CoeInitCmd, eni::SoeInitCmd, eni::EoeInitCmd>;

struct SlavePlan {
    std::size_t slave_index = 0;  // into EniConfig::slaves
    bool synthesized = false;     // its ESC InitCmds were made up
    std::vector<SlaveStep> steps;
};

struct TransitionPlan {
    eni::Transition transition = eni::Transition::IP;
    std::vector<eni::EcatCmd> master_before;
    std::vector<SlavePlan> slaves;  // present slaves in ring order
    std::vector<eni::EcatCmd> master_after;
};

// `present[i]` tells whether EniConfig::slaves[i] takes part.
TransitionPlan plan_transition(const eni::EniConfig& eni, eni::Transition transition, const std::vector<bool>& present);

// The slaves' indices in ring order (by ring position, file order for ties).
std::vector<std::size_t> ring_order(const eni::EniConfig& eni);

}  // namespace ecpair::sequencer
