// <Master>: Info (name, MACs, EtherType), the optional MailboxStates and EoE
// sizing, and the master InitCmds (the BeforeSlave broadcasts). EAS puts its
// own settings (NIC, RNIC, CycleTime, DC...) directly under Master; they are
// logged and ignored like any unknown element.

#include "ecpair/common/bytes.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

wire::MacAddress read_mac(const Element& element) {
    const auto text = element.text();
    const auto mac = wire::MacAddress::parse(text);
    if (!mac) element.fail(in_quotes(text) + " is not a MAC address (expected 12 hex digits)");
    return *mac;
}

// The file writes the EtherType's two bytes little-endian first: "a488" is 0x88A4.
std::uint16_t read_ether_type(const Element& element) {
    const auto bytes = element.hex_binary();
    if (bytes.size() != 2) element.fail(in_quotes(element.text()) + " is not an EtherType (expected 4 hex digits)");
    return load_le<std::uint16_t>(bytes);
}

MasterInfo read_master_info(const Element& info) {
    MasterInfo result;
    result.name = info.optional_text("Name");
    if (const auto destination = info.child("Destination")) result.destination = read_mac(*destination);
    if (const auto source = info.child("Source")) result.source = read_mac(*source);
    if (const auto ether_type = info.child("EtherType")) result.ether_type = read_ether_type(*ether_type);
    info.log_unread_children();
    return result;
}

MailboxStates read_mailbox_states(const Element& states) {
    MailboxStates result;
    result.start_addr = states.required_number<std::uint32_t>("StartAddr");
    result.count = states.required_number<std::uint32_t>("Count");
    states.log_unread_children();
    return result;
}

EoeSettings read_eoe(const Element& eoe) {
    EoeSettings result;
    result.max_ports = eoe.optional_number<std::uint32_t>("MaxPorts").value_or(0);
    result.max_frames = eoe.optional_number<std::uint32_t>("MaxFrames").value_or(0);
    result.max_macs = eoe.optional_number<std::uint32_t>("MaxMACs").value_or(0);
    eoe.log_unread_children();
    return result;
}

}  // namespace

Master read_master(const Element& master) {
    Master result;
    result.info = read_master_info(master.required_child("Info"));
    if (const auto states = master.child("MailboxStates")) result.mailbox_states = read_mailbox_states(*states);
    if (const auto eoe = master.child("EoE")) result.eoe = read_eoe(*eoe);
    result.init_cmds = read_init_cmds(master);
    master.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
