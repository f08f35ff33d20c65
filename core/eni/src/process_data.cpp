// <ProcessData>: the slave's slice of the process image (Send = outputs,
// Recv = inputs, as bit ranges), its SyncManagers Sm0..Sm7 and the PDOs with
// their entries. Couplers write <ProcessData/>; EAS writes only Send/Recv.

#include <string>

#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

constexpr std::uint8_t kSyncManagerCount = 8;

BitRange read_bit_range(const Element& range) {
    BitRange result;
    result.bit_start = range.required_number<std::uint32_t>("BitStart");
    result.bit_length = range.required_number<std::uint32_t>("BitLength");
    range.log_unread_children();
    return result;
}

SyncManager read_sync_manager(const Element& sm, std::uint8_t index) {
    SyncManager result;
    result.index = index;
    if (const auto type = sm.child("Type")) result.type = type->value(parse_sm_type(type->text()));
    result.min_size = sm.optional_number<std::uint16_t>("MinSize");
    result.max_size = sm.optional_number<std::uint16_t>("MaxSize");
    result.default_size = sm.optional_number<std::uint16_t>("DefaultSize");
    result.start_address = sm.optional_number<std::uint16_t>("StartAddress");
    result.control_byte = sm.optional_number<std::uint8_t>("ControlByte");
    result.enable = sm.optional_boolean("Enable");
    for (const auto& pdo : sm.children("Pdo")) result.pdos.push_back(pdo.number<std::uint16_t>());
    sm.log_unread_children();
    return result;
}

PdoEntry read_entry(const Element& entry) {
    PdoEntry result;
    result.index = entry.required_number<std::uint16_t>("Index");
    result.subindex = entry.optional_number<std::uint8_t>("SubIndex").value_or(0);
    result.bit_length = entry.required_number<std::uint16_t>("BitLen");
    result.name = entry.optional_text("Name");
    result.data_type = entry.optional_text("DataType");
    entry.log_unread_children();
    return result;
}

Pdo read_pdo(const Element& pdo) {
    Pdo result;
    result.index = pdo.required_number<std::uint16_t>("Index");
    result.name = pdo.optional_text("Name");
    result.sm = pdo.attribute_number<std::uint8_t>("Sm");
    if (result.sm && *result.sm >= kSyncManagerCount) {
        pdo.fail_attribute("Sm", in_quotes(std::to_string(*result.sm)) + " is out of range 0..7");
    }
    result.fixed = pdo.attribute_boolean("Fixed").value_or(false);
    result.mandatory = pdo.attribute_boolean("Mandatory").value_or(false);
    for (const auto& exclude : pdo.children("Exclude")) result.excludes.push_back(exclude.number<std::uint16_t>());
    for (const auto& entry : pdo.children("Entry")) result.entries.push_back(read_entry(entry));
    pdo.log_unread_children();
    return result;
}

}  // namespace

ProcessData read_process_data(const Element& process_data) {
    ProcessData result;
    if (const auto send = process_data.child("Send")) result.send = read_bit_range(*send);
    if (const auto recv = process_data.child("Recv")) result.recv = read_bit_range(*recv);
    for (std::uint8_t index = 0; index < kSyncManagerCount; ++index) {
        if (const auto sm = process_data.child("Sm" + std::to_string(index))) {
            result.sync_managers.push_back(read_sync_manager(*sm, index));
        }
    }
    for (const auto& pdo : process_data.children("TxPdo")) result.tx_pdos.push_back(read_pdo(pdo));
    for (const auto& pdo : process_data.children("RxPdo")) result.rx_pdos.push_back(read_pdo(pdo));
    process_data.log_unread_children();
    return result;
}

}  // namespace ecpair::eni::detail
