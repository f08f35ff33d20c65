// Register InitCmds (Master and Slave <InitCmds>) and Hot-Connect
// IdentifyCmds: the same shape, except that an IdentifyCmd belongs to no
// transition. Data comes as hexBinary <Data> or as <DataLength> zero bytes;
// when a file gives both they must agree.

#include <fmt/format.h>

#include "ecpair/wire/constants.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

std::vector<std::uint8_t> read_datagram_data(const Element& data) {
    auto bytes = data.hex_binary();
    if (bytes.size() > wire::kMaxDatagramData) {
        data.fail(fmt::format("{} bytes of data, more than one datagram carries ({})", bytes.size(),
                              wire::kMaxDatagramData));
    }
    return bytes;
}

std::vector<std::uint8_t> read_cmd_data(const Element& cmd) {
    const auto data = cmd.child("Data");
    const auto data_length = cmd.child("DataLength");
    if (!data_length) return data ? read_datagram_data(*data) : std::vector<std::uint8_t>{};
    const std::uint16_t length = read_datagram_length(*data_length);
    if (!data) return std::vector<std::uint8_t>(length, 0);
    auto bytes = read_datagram_data(*data);
    if (bytes.size() != length) {
        data_length.value().fail(fmt::format("DataLength {} does not match the {} bytes of <Data>", length, bytes.size()));
    }
    return bytes;
}

Validate read_validate(const Element& validate) {
    Validate result;
    const auto data = validate.required_child("Data");
    result.data = read_datagram_data(data);
    if (const auto mask = validate.child("DataMask")) {
        result.mask = read_datagram_data(*mask);
        if (result.mask.size() != result.data.size()) {
            mask->fail(fmt::format("DataMask has {} byte(s) but Data has {}", result.mask.size(), result.data.size()));
        }
    }
    result.timeout = std::chrono::milliseconds(validate.optional_number<std::uint32_t>("Timeout").value_or(0));
    validate.log_unread_children();
    return result;
}

}  // namespace

EcatCmd read_ecat_cmd(const Element& cmd, EcatCmdKind kind) {
    EcatCmd result;
    result.source_line = cmd.line();
    result.transitions = read_transitions(cmd, kind == EcatCmdKind::InitCmd);
    result.before_slave = cmd.optional_boolean("BeforeSlave").value_or(false);
    result.comment = cmd.optional_text("Comment");
    if (const auto requires_ = cmd.child("Requires")) result.requires_ = requires_->value(parse_requires(requires_->text()));

    const auto command = cmd.required_child("Cmd");
    result.command = command.value(parse_command_code(command.text()));
    const auto address = read_datagram_address(cmd, result.command);
    result.adp = address.adp;
    result.ado = address.ado;
    result.logical_address = address.logical;

    result.data = read_cmd_data(cmd);
    result.expected_wkc = cmd.optional_number<std::uint16_t>("Cnt");
    result.retries = cmd.optional_number<std::uint32_t>("Retries").value_or(0);
    if (const auto timeout = cmd.optional_number<std::uint32_t>("Timeout")) {
        result.timeout = std::chrono::milliseconds(*timeout);
    }
    if (const auto validate = cmd.child("Validate")) result.validate = read_validate(*validate);
    cmd.log_unread_children();
    return result;
}

std::vector<EcatCmd> read_init_cmds(const Element& owner) {
    std::vector<EcatCmd> cmds;
    const auto init_cmds = owner.child("InitCmds");
    if (!init_cmds) return cmds;
    for (const auto& cmd : init_cmds->children("InitCmd")) cmds.push_back(read_ecat_cmd(cmd, EcatCmdKind::InitCmd));
    init_cmds->log_unread_children();
    return cmds;
}

}  // namespace ecpair::eni::detail
