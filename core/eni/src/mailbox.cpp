// <Mailbox>: the mailbox SyncManager areas (normal and BootStrap), how the
// master learns of new mail (PollTime or a MailboxStates StatusBitAddr), the
// supported protocols and the CoE, EoE and SoE InitCmds, kept as data.
// Profile ChannelInfo and FoE details are not used and are ignored.

#include <string_view>
#include <utility>

#include "ecpair/common/log.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

// Start and Length; the caller reads what else its area has and then logs the rest.
MailboxArea read_area(const Element& area) {
    MailboxArea result;
    result.start = area.required_number<std::uint16_t>("Start");
    result.length = area.required_number<std::uint16_t>("Length");
    return result;
}

CoeInitCmd read_coe_init_cmd(const Element& cmd) {
    CoeInitCmd result;
    result.source_line = cmd.line();
    result.fixed = cmd.attribute_boolean("Fixed").value_or(false);
    result.complete_access = cmd.attribute_boolean("CompleteAccess").value_or(false);
    result.transitions = read_transitions(cmd, true);
    result.comment = cmd.optional_text("Comment");
    result.timeout = std::chrono::milliseconds(cmd.optional_number<std::uint32_t>("Timeout").value_or(0));
    if (const auto ccs = cmd.child("Ccs")) {
        result.ccs = ccs->number<std::uint8_t>();
        if (result.ccs != 1 && result.ccs != 2) ccs->fail(in_quotes(ccs->text()) + " is not 1 (download) or 2 (upload)");
    }
    // Index is decimal in every real file (7186 = 0x1C12); #x hex is accepted too.
    result.index = cmd.required_number<std::uint16_t>("Index");
    result.subindex = cmd.optional_number<std::uint8_t>("SubIndex").value_or(0);
    if (const auto data = cmd.child("Data")) result.data = data->hex_binary();
    result.disabled = cmd.optional_boolean("Disabled").value_or(false);
    cmd.log_unread_children();
    return result;
}

EoeInitCmd read_eoe_init_cmd(const Element& cmd) {
    EoeInitCmd result;
    result.source_line = cmd.line();
    result.fixed = cmd.attribute_boolean("Fixed").value_or(false);
    result.transitions = read_transitions(cmd, true);
    result.comment = cmd.optional_text("Comment");
    result.timeout = std::chrono::milliseconds(cmd.optional_number<std::uint32_t>("Timeout").value_or(0));
    if (const auto data = cmd.child("Data")) result.data = data->hex_binary();
    result.disabled = cmd.optional_boolean("Disabled").value_or(false);
    cmd.log_unread_children();
    return result;
}

SoeInitCmd read_soe_init_cmd(const Element& cmd) {
    SoeInitCmd result;
    result.source_line = cmd.line();
    result.fixed = cmd.attribute_boolean("Fixed").value_or(false);
    result.transitions = read_transitions(cmd, true);
    result.comment = cmd.optional_text("Comment");
    result.timeout = std::chrono::milliseconds(cmd.optional_number<std::uint32_t>("Timeout").value_or(0));
    if (const auto opcode = cmd.child("OpCode")) {
        result.opcode = opcode->number<std::uint8_t>();
        if (result.opcode != 1 && result.opcode != 3) {
            opcode->fail(in_quotes(opcode->text()) + " is not 3 (write) or 1 (read)");
        }
    }
    if (const auto drive = cmd.child("DriveNo")) {
        result.drive_no = drive->number<std::uint8_t>();
        if (result.drive_no > 7) drive->fail(in_quotes(drive->text()) + " is not a drive number 0..7");
    }
    result.idn = cmd.required_number<std::uint16_t>("IDN");
    result.elements = cmd.optional_number<std::uint8_t>("Elements").value_or(0x40);
    result.attribute = cmd.optional_number<std::uint8_t>("Attribute").value_or(0);
    if (const auto data = cmd.child("Data")) result.data = data->hex_binary();
    result.disabled = cmd.optional_boolean("Disabled").value_or(false);
    cmd.log_unread_children();
    return result;
}

// The <InitCmds><InitCmd>* of a protocol element (<CoE>, <EoE>, <SoE>).
template <class ReadCmd>
auto read_protocol_init_cmds(const Element& protocol, ReadCmd read_cmd) {
    std::vector<decltype(read_cmd(protocol))> cmds;
    if (const auto init_cmds = protocol.child("InitCmds")) {
        for (const auto& cmd : init_cmds->children("InitCmd")) cmds.push_back(read_cmd(cmd));
        init_cmds->log_unread_children();
    }
    return cmds;
}

}  // namespace

Mailbox read_mailbox(const Element& mailbox) {
    Mailbox result;
    result.data_link_layer = std::string(mailbox.attribute("DataLinkLayer").value_or(""));
    if (const auto send = mailbox.child("Send")) {
        result.send = read_area(*send);
        send->log_unread_children();
    }
    if (const auto recv = mailbox.child("Recv")) {
        result.recv = read_area(*recv);
        result.poll_time_ms = recv->optional_number<std::uint32_t>("PollTime");
        result.status_bit_addr = recv->optional_number<std::uint32_t>("StatusBitAddr");
        recv->log_unread_children();
    }
    if (const auto bootstrap = mailbox.child("BootStrap")) {
        if (const auto send = bootstrap->child("Send")) {
            result.bootstrap_send = read_area(*send);
            send->log_unread_children();
        }
        if (const auto recv = bootstrap->child("Recv")) {
            result.bootstrap_recv = read_area(*recv);
            recv->log_unread_children();
        }
        bootstrap->log_unread_children();
    }

    for (const auto& protocol : mailbox.children("Protocol")) {
        if (const auto bit = parse_protocol(protocol.text())) {
            result.protocols = static_cast<std::uint16_t>(result.protocols | *bit);
        } else {
            logger("eni")->warn("line {}: {}: unknown mailbox protocol {} ignored", protocol.line(), protocol.path(),
                                in_quotes(protocol.text()));
        }
    }
    // A protocol with its own element is supported even when no <Protocol> says so (Advantech).
    static constexpr std::pair<std::string_view, MailboxProtocol> kProtocolElements[] = {
        {"AoE", kAoE}, {"EoE", kEoE}, {"CoE", kCoE}, {"FoE", kFoE}, {"SoE", kSoE}, {"VoE", kVoE}};
    for (const auto& [name, bit] : kProtocolElements) {
        if (mailbox.has_child(name)) result.protocols = static_cast<std::uint16_t>(result.protocols | bit);
    }
    if (const auto coe = mailbox.child("CoE")) {
        result.coe_init_cmds = read_protocol_init_cmds(*coe, read_coe_init_cmd);
        coe->log_unread_children();
    }
    if (const auto eoe = mailbox.child("EoE")) {
        result.eoe_init_cmds = read_protocol_init_cmds(*eoe, read_eoe_init_cmd);
        eoe->log_unread_children();
    }
    if (const auto soe = mailbox.child("SoE")) {
        result.soe_init_cmds = read_protocol_init_cmds(*soe, read_soe_init_cmd);
        soe->log_unread_children();
    }
    // ecpair runs the CoE, EoE and SoE InitCmds; any other protocol's would be
    // skipped in silence, so a file that has them is refused.
    for (const std::string_view name : {"AoE", "FoE", "VoE"}) {
        const auto protocol = mailbox.child(name);
        if (!protocol) continue;
        if (const auto init_cmds = protocol->child("InitCmds"); init_cmds && init_cmds->has_child("InitCmd")) {
            init_cmds->fail(std::string(name) + " InitCmds are not supported: ecpair runs the CoE, EoE and SoE "
                                                "InitCmds of a mailbox and cannot execute these");
        }
    }
    if (const auto aoe = mailbox.child("AoE")) {
        if (aoe->has_child("NetId")) result.aoe_net_id = aoe->optional_text("NetId");
        aoe->log_unread_children();
    }
    mailbox.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
