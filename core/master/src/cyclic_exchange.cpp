#include "ecpair/master/cyclic_exchange.hpp"

#include <algorithm>

namespace ecpair::master {
namespace {

constexpr std::array<eni::SlaveState, 3> kCyclicStates = {eni::SlaveState::Preop, eni::SlaveState::Safeop,
                                                          eni::SlaveState::Op};

}  // namespace

std::size_t CyclicExchange::state_slot(eni::SlaveState state) {
    switch (state) {
        case eni::SlaveState::Preop: return 0;
        case eni::SlaveState::Safeop: return 1;
        case eni::SlaveState::Op: return 2;
        default: return 3;  // INIT/BOOT: no cyclic datagrams
    }
}

CyclicExchange::CyclicExchange(CyclicPlan plan) : plan_(std::move(plan)) {
    active_.resize(plan_.frames.size());
    last_state_slot_.assign(plan_.frames.size(), 3);
    for (const auto& frame : plan_.frames) {
        first_.push_back(expected_.size());
        for (const auto& d : frame.datagrams) expected_.push_back(d.expected_wkc);
    }
    last_wkc_.assign(expected_.size(), 0);
    frame_irq_.assign(plan_.frames.size(), 0);
    for (std::size_t f = 0; f < plan_.frames.size(); ++f) {
        const auto& datagrams = plan_.frames[f].datagrams;
        for (std::size_t s = 0; s < kCyclicStates.size(); ++s) {
            for (std::size_t d = 0; d < datagrams.size(); ++d) {
                if (datagrams[d].states.contains(kCyclicStates[s])) {
                    active_[f][s].push_back(static_cast<std::uint16_t>(d));
                }
            }
        }
    }
}

bool CyclicExchange::active(std::size_t index, eni::SlaveState state) const {
    const auto slot = state_slot(state);
    return slot < 3 && !active_[index][slot].empty();
}

Bytes CyclicExchange::build(std::size_t index, eni::SlaveState state, ConstBytes outputs,
                            const wire::EthernetHeader& ethernet, Bytes buffer) {
    const auto slot = state_slot(state);
    last_state_slot_[index] = slot;
    wire::FrameBuilder builder(buffer, ethernet);
    if (slot >= 3) return builder.finish();
    const auto& datagrams = plan_.frames[index].datagrams;
    for (const std::uint16_t d : active_[index][slot]) {
        const PlannedDatagram& planned = datagrams[d];
        wire::DatagramHeader header;
        header.command = planned.command;
        header.index = static_cast<std::uint8_t>(d);
        header.address = planned.address;
        auto view = builder.append(header, planned.length);  // the plan packed frames so this fits
        if (planned.output_offset && *planned.output_offset + planned.length <= outputs.size()) {
            std::copy_n(outputs.begin() + *planned.output_offset, planned.length, view->data().begin());
        }
    }
    return builder.finish();
}

bool CyclicExchange::counters_complete(std::size_t index, const wire::ConstFrameView& returned) const {
    const auto slot = last_state_slot_[index];
    if (slot >= 3) return false;
    const auto& list = active_[index][slot];
    if (returned.datagram_count() != list.size()) return false;
    bool any = false;
    std::size_t i = 0;
    const auto& datagrams = plan_.frames[index].datagrams;
    for (const auto d : returned) {
        const auto& expected = expected_[first_[index] + list[i]];
        const auto& planned = datagrams[list[i++]];
        if (!expected || slot < state_slot(planned.valid_from)) continue;
        if (d.wkc() != *expected) return false;
        any = true;
    }
    return any;
}

void CyclicExchange::set_expected(const std::vector<std::optional<std::uint16_t>>& expected) {
    std::copy_n(expected.begin(), std::min(expected.size(), expected_.size()), expected_.begin());
}

FrameCompletion CyclicExchange::complete(std::size_t index, const wire::ConstFrameView& returned, Bytes inputs,
                                         std::vector<WkcMismatch>& mismatches) {
    FrameCompletion result;
    const auto slot = last_state_slot_[index];
    if (slot >= 3) return result;
    const auto& list = active_[index][slot];
    const auto& datagrams = plan_.frames[index].datagrams;
    if (returned.datagram_count() != list.size()) {
        result.layout_ok = false;
        return result;
    }
    std::size_t i = 0;
    std::uint16_t irq = 0;
    for (const auto d : returned) {
        irq = static_cast<std::uint16_t>(irq | d.irq());
        const std::size_t flat = first_[index] + list[i];
        const PlannedDatagram& planned = datagrams[list[i++]];
        if (d.command() != planned.command || d.length() != planned.length) {
            result.layout_ok = false;
            return result;
        }
        ++result.datagrams;
        if (planned.input_offset && *planned.input_offset + planned.length <= inputs.size()) {
            std::copy(d.data().begin(), d.data().end(), inputs.begin() + *planned.input_offset);
        }
        last_wkc_[flat] = d.wkc();
        // Not before the state its WKC can be right in (process data: SAFEOP).
        const auto& expected = expected_[flat];
        if (expected && slot >= state_slot(planned.valid_from) && d.wkc() != *expected) {
            ++result.wkc_errors;
            if (mismatches.size() < mismatches.capacity()) {
                mismatches.push_back(WkcMismatch{static_cast<std::uint16_t>(index), &planned, *expected, d.wkc()});
            }
        }
    }
    frame_irq_[index] = irq;
    return result;
}

std::uint16_t CyclicExchange::irq() const {
    std::uint16_t irq = 0;
    for (const auto f : frame_irq_) irq = static_cast<std::uint16_t>(irq | f);
    return irq;
}

}  // namespace ecpair::master
