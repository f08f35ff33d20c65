// The small helpers model.hpp declares: names of states, transitions and
// SyncManager types, the states a transition connects, and the LRW question.

#include "ecpair/eni/model.hpp"

#include <algorithm>

namespace ecpair::eni {

std::string_view to_string(SlaveState state) {
    switch (state) {
        case SlaveState::Init: return "INIT";
        case SlaveState::Preop: return "PREOP";
        case SlaveState::Boot: return "BOOT";
        case SlaveState::Safeop: return "SAFEOP";
        case SlaveState::Op: return "OP";
    }
    return "UNKNOWN";
}

std::string_view to_string(Transition t) {
    switch (t) {
        case Transition::IP: return "IP";
        case Transition::PS: return "PS";
        case Transition::SO: return "SO";
        case Transition::SP: return "SP";
        case Transition::OP: return "OP";
        case Transition::OS: return "OS";
        case Transition::PI: return "PI";
        case Transition::SI: return "SI";
        case Transition::OI: return "OI";
        case Transition::IB: return "IB";
        case Transition::BI: return "BI";
        case Transition::II: return "II";
        case Transition::PP: return "PP";
    }
    return "??";
}

namespace {

struct TransitionStates {
    SlaveState from;
    SlaveState to;
};

// Each code is "<from letter><to letter>": I(nit), P(reop), S(afeop), O(p), B(oot).
TransitionStates states_of(Transition t) {
    using S = SlaveState;
    switch (t) {
        case Transition::IP: return {S::Init, S::Preop};
        case Transition::PS: return {S::Preop, S::Safeop};
        case Transition::SO: return {S::Safeop, S::Op};
        case Transition::SP: return {S::Safeop, S::Preop};
        case Transition::OP: return {S::Op, S::Preop};
        case Transition::OS: return {S::Op, S::Safeop};
        case Transition::PI: return {S::Preop, S::Init};
        case Transition::SI: return {S::Safeop, S::Init};
        case Transition::OI: return {S::Op, S::Init};
        case Transition::IB: return {S::Init, S::Boot};
        case Transition::BI: return {S::Boot, S::Init};
        case Transition::II: return {S::Init, S::Init};
        case Transition::PP: return {S::Preop, S::Preop};
    }
    return {S::Init, S::Init};
}

}  // namespace

SlaveState from_state(Transition t) {
    return states_of(t).from;
}

SlaveState to_state(Transition t) {
    return states_of(t).to;
}

std::string_view to_string(SmType type) {
    switch (type) {
        case SmType::Unused: return "Unused";
        case SmType::MailboxOut: return "MBoxOut";
        case SmType::MailboxIn: return "MBoxIn";
        case SmType::Outputs: return "Outputs";
        case SmType::Inputs: return "Inputs";
    }
    return "Unknown";
}

bool EniConfig::uses_logical_read_write() const {
    return std::any_of(cyclic.begin(), cyclic.end(), [](const Cyclic& c) {
        return std::any_of(c.frames.begin(), c.frames.end(), [](const CyclicFrame& frame) {
            return std::any_of(frame.cmds.begin(), frame.cmds.end(),
                               [](const CyclicCmd& cmd) { return cmd.command == wire::Command::Lrw; });
        });
    });
}

}  // namespace ecpair::eni
