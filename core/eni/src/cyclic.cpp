// <Cyclic>: the cycle time and the frames the master sends every cycle, each
// a list of datagrams with the states they are sent in, their address, size,
// expected working counter and where their data sits in the process image.
// The offsets are kept as written: EC-Engineer and TwinCAT mean different
// things by them (docs/ENI.md), and the master decides how to read them.

#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

CyclicCmd read_cyclic_cmd(const Element& cmd) {
    CyclicCmd result;
    result.source_line = cmd.line();
    for (const auto& state : cmd.children("State")) result.states.add(state.value(parse_state(state.text())));
    if (result.states.empty()) cmd.fail_missing("State");
    result.comment = cmd.optional_text("Comment");
    const auto command = cmd.required_child("Cmd");
    result.command = command.value(parse_command_code(command.text()));
    const auto address = read_datagram_address(cmd, result.command);
    result.adp = address.adp;
    result.ado = address.ado;
    result.logical_address = address.logical;
    result.data_length = read_datagram_length(cmd.required_child("DataLength"));
    result.expected_wkc = cmd.optional_number<std::uint16_t>("Cnt");
    result.input_offset = cmd.optional_number<std::uint32_t>("InputOffs");
    result.output_offset = cmd.optional_number<std::uint32_t>("OutputOffs");
    cmd.log_unread_children();
    return result;
}

CyclicFrame read_frame(const Element& frame) {
    CyclicFrame result;
    result.source_line = frame.line();
    for (const auto& cmd : frame.children("Cmd")) result.cmds.push_back(read_cyclic_cmd(cmd));
    frame.log_unread_children();
    return result;
}

}  // namespace

Cyclic read_cyclic(const Element& cyclic) {
    Cyclic result;
    result.cycle_time_us = cyclic.optional_number<std::uint32_t>("CycleTime");
    for (const auto& frame : cyclic.children("Frame")) result.frames.push_back(read_frame(frame));
    cyclic.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
