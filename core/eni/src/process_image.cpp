// <ProcessImage>: the size of the input and output images and the named
// variables in them. Variables are kept as written, even past ByteSize:
// TwinCAT lists its InfoData variables (ChangeCount, DevId, AmsNetId...)
// beyond the 1536-byte frame image, so whoever maps a variable onto the image
// has to check its bounds.

#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

Variable read_variable(const Element& variable) {
    Variable result;
    result.name = variable.required_child("Name").text();
    result.comment = variable.optional_text("Comment");
    result.data_type = variable.optional_text("DataType");
    result.bit_size = variable.required_number<std::uint32_t>("BitSize");
    result.bit_offset = variable.required_number<std::uint32_t>("BitOffs");
    variable.log_unread_children();
    return result;
}

ProcessImageSection read_section(const Element& section) {
    ProcessImageSection result;
    result.byte_size = section.required_number<std::uint32_t>("ByteSize");
    for (const auto& variable : section.children("Variable")) result.variables.push_back(read_variable(variable));
    section.log_unread_children();
    return result;
}

}  // namespace

ProcessImage read_process_image(const Element& process_image) {
    ProcessImage result;
    if (const auto inputs = process_image.child("Inputs")) result.inputs = read_section(*inputs);
    if (const auto outputs = process_image.child("Outputs")) result.outputs = read_section(*outputs);
    process_image.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
