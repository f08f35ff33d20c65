// <Slave>: identity (Info), process data, mailbox, register InitCmds, the
// upstream port (PreviousPort), DC settings and an optional Hot-Connect group.
// ring_position is filled in later by check_slaves(), which needs every slave.

#include <cctype>

#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

Identification read_identification(const Element& identification) {
    Identification result;
    result.ado = identification.required_number<std::uint16_t>("Ado");
    // TwinCAT and EAS write the expected value as an attribute; accept a child too.
    result.value = identification.attribute_number<std::uint16_t>("Value");
    if (!result.value) result.value = identification.optional_number<std::uint16_t>("Value");
    result.enabled = identification.attribute_boolean("EnableIdentification").value_or(true);
    identification.log_unread_children();
    return result;
}

SlaveInfo read_info(const Element& info, const Element& slave) {
    SlaveInfo result;
    result.name = info.optional_text("Name");
    result.phys_addr = info.required_number<std::uint16_t>("PhysAddr");
    result.auto_inc_addr = info.optional_number<std::uint16_t>("AutoIncAddr", Negative::TwosComplement).value_or(0);
    // EAS repeats Physics as an attribute of <Slave>.
    result.physics = info.has_child("Physics") ? info.optional_text("Physics")
                                               : std::string(slave.attribute("Physics").value_or(""));
    result.vendor_id = info.required_number<std::uint32_t>("VendorId", Negative::TwosComplement);
    result.product_code = info.required_number<std::uint32_t>("ProductCode", Negative::TwosComplement);
    result.revision_no = info.optional_number<std::uint32_t>("RevisionNo", Negative::TwosComplement).value_or(0);
    result.serial_no = info.optional_number<std::uint32_t>("SerialNo", Negative::TwosComplement);
    if (const auto identification = info.child("Identification")) {
        result.identification = read_identification(*identification);
    }
    info.log_unread_children();
    return result;
}

PreviousPort read_previous_port(const Element& previous) {
    PreviousPort result;
    result.selected = previous.attribute_boolean("Selected").value_or(false);
    const auto port = previous.required_child("Port");
    const auto letter = port.text();
    const char upper = letter.size() == 1 ? static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0]))) : '?';
    if (upper < 'A' || upper > 'D') port.fail(in_quotes(letter) + " is not a port (expected A, B, C or D)");
    result.port = upper;
    result.phys_addr = previous.required_number<std::uint16_t>("PhysAddr");
    previous.log_unread_children();
    return result;
}

DistributedClocks read_dc(const Element& dc) {
    DistributedClocks result;
    result.potential_reference_clock = dc.optional_boolean("PotentialReferenceClock").value_or(false);
    result.reference_clock = dc.optional_boolean("ReferenceClock").value_or(false);
    result.cycle_time0_ns = dc.optional_number<std::uint32_t>("CycleTime0");
    result.cycle_time1_ns = dc.optional_number<std::uint32_t>("CycleTime1");
    result.shift_time_ns = dc.optional_number<std::int32_t>("ShiftTime");
    dc.log_unread_children();
    return result;
}

HotConnect read_hot_connect(const Element& hot_connect) {
    HotConnect result;
    result.source_line = hot_connect.line();
    result.group_name = hot_connect.optional_text("GroupName");
    const auto member_count = hot_connect.required_child("GroupMemberCnt");
    result.group_member_count = member_count.number<std::uint32_t>();
    if (result.group_member_count == 0) member_count.fail("a Hot-Connect group has at least one member (its head)");
    for (const auto& cmd : hot_connect.children("IdentifyCmd")) {
        result.identify_cmds.push_back(read_ecat_cmd(cmd, EcatCmdKind::IdentifyCmd));
    }
    hot_connect.log_unread_children();
    return result;
}

bool has_init_cmds(const Element& slave) {
    const auto init_cmds = slave.child("InitCmds");
    return init_cmds && !init_cmds->children("InitCmd").empty();
}

}  // namespace

bool is_passive_slave(const Element& slave) {
    const auto info = slave.child("Info");
    return info && !info->has_child("PhysAddr") && !info->has_child("AutoIncAddr") && !has_init_cmds(slave);
}

PassiveSlave read_passive_slave(const Element& slave, std::size_t file_index) {
    PassiveSlave result;
    result.source_line = slave.line();
    result.file_index = file_index;
    const auto info = slave.required_child("Info");
    result.name = info.optional_text("Name");
    result.vendor_id = info.optional_number<std::uint32_t>("VendorId", Negative::TwosComplement);
    result.product_code = info.optional_number<std::uint32_t>("ProductCode", Negative::TwosComplement);
    result.revision_no = info.optional_number<std::uint32_t>("RevisionNo", Negative::TwosComplement);
    (void)info.child("Physics");
    info.log_unread_children();
    // Without an ESC there is nothing to exchange: process data would be lost in silence.
    if (const auto process_data = slave.child("ProcessData")) {
        for (const auto* direction : {"Send", "Recv"}) {
            const auto range = process_data->child(direction);
            if (range && range->optional_number<std::uint32_t>("BitLength").value_or(0) != 0) {
                range->fail("a slave without PhysAddr, AutoIncAddr and InitCmds has no ESC (a passive terminal) and "
                            "cannot exchange process data; give it its PhysAddr and InitCmds");
            }
        }
    }
    for (const auto& previous : slave.children("PreviousPort")) result.previous_ports.push_back(read_previous_port(previous));
    (void)slave.child("InitCmds");
    slave.log_unread_children();
    return result;
}

Slave read_slave(const Element& slave) {
    Slave result;
    result.source_line = slave.line();
    result.info = read_info(slave.required_child("Info"), slave);
    if (const auto process_data = slave.child("ProcessData")) result.process_data = read_process_data(*process_data);
    if (const auto mailbox = slave.child("Mailbox")) result.mailbox = read_mailbox(*mailbox);
    result.init_cmds = read_init_cmds(slave);
    for (const auto& previous : slave.children("PreviousPort")) {
        result.previous_ports.push_back(read_previous_port(previous));
    }
    if (const auto dc = slave.child("DC")) result.dc = read_dc(*dc);
    if (const auto hot_connect = slave.child("HotConnect")) result.hot_connect = read_hot_connect(*hot_connect);
    slave.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
