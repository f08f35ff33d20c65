// The fields every datagram-shaped ENI command shares: where it addresses
// (Adp/Ado or Addr), how much data it carries, and in which transitions an
// InitCmd runs.

#include "ecpair/wire/constants.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {

DatagramAddress read_datagram_address(const Element& cmd, wire::Command command) {
    const auto addr = cmd.optional_number<std::uint32_t>("Addr");
    const auto adp = cmd.optional_number<std::uint16_t>("Adp", Negative::TwosComplement);
    const auto ado = cmd.optional_number<std::uint16_t>("Ado");

    DatagramAddress address;
    if (wire::addressing_of(command) == wire::Addressing::Logical) {
        if (addr) {
            address.logical = *addr;
        } else if (ado) {
            address.logical = static_cast<std::uint32_t>(adp.value_or(0)) | (static_cast<std::uint32_t>(*ado) << 16);
        } else {
            cmd.fail_missing("Addr");
        }
        return address;
    }
    if (ado) {
        address.adp = adp.value_or(0);
        address.ado = *ado;
    } else if (addr) {
        address.adp = static_cast<std::uint16_t>(*addr & 0xFFFF);
        address.ado = static_cast<std::uint16_t>(*addr >> 16);
    } else {
        cmd.fail_missing("Ado");
    }
    return address;
}

std::uint16_t read_datagram_length(const Element& data_length) {
    const auto length = data_length.number<std::uint16_t>();
    if (length > wire::kMaxDatagramData) {
        data_length.fail(in_quotes(data_length.text()) + " is out of range 0.." + std::to_string(wire::kMaxDatagramData) +
                         " (the most data one datagram carries)");
    }
    return length;
}

TransitionSet read_transitions(const Element& cmd, bool required) {
    TransitionSet transitions;
    for (const auto& transition : cmd.children("Transition")) {
        transitions.add(transition.value(parse_transition(transition.text())));
    }
    if (required && transitions.empty()) cmd.fail_missing("Transition");
    return transitions;
}

}  // namespace ecpair::eni::detail
