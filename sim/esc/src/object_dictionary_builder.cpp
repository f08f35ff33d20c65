// ObjectDictionary::for_slave: the objects a slave has, worked out from its
// description in five passes (docs/ESC_EMULATION.md "CoE server"):
//
//  1. standard objects: 0x1000 device type (0: the ENI carries no profile),
//     0x1008 device name, 0x1009/0x100A versions ("ecsim"), 0x1018 identity,
//     0x1C00 SyncManager communication types;
//  2. a PDO mapping object for every RxPDO/TxPDO of the ENI (an entry longer
//     than 255 bits is split, as in the SII, so the bit total stays right)
//     and the application objects their entries map: RxPDO objects are
//     writable, TxPDO objects read-only, all zero;
//  3. a PDO assignment object 0x1C10+n for every process data SyncManager,
//     holding the PDOs the layout assigns to it, with room for every PDO of
//     its direction;
//  4. every object and subindex a CoE InitCmd of the ENI writes, with the
//     written size (Advantech's Ccs=2 commands carrying data count as
//     writes). A written entry becomes writable; a mapping or assignment
//     object grows to the entries the command writes. CompleteAccess to an
//     object the ENI does not otherwise describe cannot be pre-created (the
//     entry sizes are unknown): it is logged and its download will abort;
//  5. subindex 0 of every record = its highest subindex.
// Every entry also gets what SDO Information describes: its CoE data type
// (the ENI's <DataType> for mapped objects, the standard types for the
// standard objects, by size for what only InitCmds reveal), bit length,
// name and whether an RxPDO or TxPDO maps it.

#include <algorithm>
#include <string_view>

#include <fmt/format.h>

#include "coe_data_types.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sim/esc.hpp"
#include "ecpair/sim/object_dictionary.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "esc_layout.hpp"

namespace ecpair::sim {
namespace {

constexpr std::size_t kMaxEntries = 255;   // subindex 0 counts them in 8 bits
constexpr std::uint16_t kMaxMappedBits = 255;  // the bit length field of a mapping entry
constexpr std::size_t kMappingEntrySize = 4;
constexpr std::size_t kAssignmentEntrySize = 2;

using Objects = std::map<std::uint16_t, DictionaryObject>;
namespace coe_type = wire::coe_type;

std::vector<std::uint8_t> little_endian(std::uint32_t value, std::size_t size) {
    std::vector<std::uint8_t> bytes(size);
    for (std::size_t i = 0; i < size && i < 4; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
    return bytes;
}

std::vector<std::uint8_t> text(std::string_view s) { return {s.begin(), s.end()}; }

ObjectKind kind_for_index(std::uint16_t index) {
    if ((index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF)) return ObjectKind::PdoMapping;
    if (index >= ObjectDictionary::kPdoAssignmentBase && index <= 0x1C2F) return ObjectKind::PdoAssignment;
    return ObjectKind::Record;
}

std::size_t pdo_entry_size(ObjectKind kind) {
    return kind == ObjectKind::PdoMapping ? kMappingEntrySize : kAssignmentEntrySize;
}

// Inserts `entry` in subindex order, or returns the entry already there.
ObjectEntry& entry_at(DictionaryObject& object, ObjectEntry entry) {
    const auto it = std::lower_bound(object.entries.begin(), object.entries.end(), entry.subindex,
                                     [](const ObjectEntry& e, std::uint8_t s) { return e.subindex < s; });
    if (it != object.entries.end() && it->subindex == entry.subindex) return *it;
    return *object.entries.insert(it, std::move(entry));
}

ObjectEntry make_entry(std::uint8_t subindex, EntryAccess access, std::vector<std::uint8_t> value,
                       std::uint16_t data_type, std::string name) {
    ObjectEntry entry;
    entry.subindex = subindex;
    entry.access = access;
    entry.value = std::move(value);
    entry.data_type = data_type;
    entry.name = std::move(name);
    return entry;
}

std::string subindex_name(std::size_t subindex) { return fmt::format("SubIndex {:03}", subindex); }

DictionaryObject variable(std::uint16_t index, std::string name, EntryAccess access, std::vector<std::uint8_t> value,
                          std::uint16_t data_type) {
    ObjectEntry entry = make_entry(0, access, std::move(value), data_type, name);
    return DictionaryObject{index, ObjectKind::Variable, std::move(name), {std::move(entry)}};
}

// A record, mapping or assignment object with subindex 0 only.
DictionaryObject with_count(std::uint16_t index, ObjectKind kind, std::string name, EntryAccess count_access) {
    return DictionaryObject{index, kind, std::move(name),
                            {make_entry(0, count_access, {0}, coe_type::kUnsigned8, "Number of entries")}};
}

std::uint16_t pdo_entry_type(ObjectKind kind) {
    return kind == ObjectKind::PdoMapping ? coe_type::kUnsigned32 : coe_type::kUnsigned16;
}

// The type of a mapped application entry: the ENI's, else by its size.
std::uint16_t mapped_type(const eni::PdoEntry& e) {
    if (const std::uint16_t type = coe_data_type(e.data_type); type != 0) return type;
    if (e.bit_length == 1) return coe_type::kBoolean;
    return coe_data_type_of_size((e.bit_length + 7u) / 8u);
}

void set_count(DictionaryObject& object, std::size_t count) {
    object.entries.front().value = {static_cast<std::uint8_t>(count)};
}

// Appends entries (zero, same access as subindex 0) until the object holds `capacity`.
void grow_pdo_object(DictionaryObject& object, std::size_t capacity) {
    capacity = std::min(capacity, kMaxEntries);
    const EntryAccess access = object.entries.front().access;
    while (object.entries.size() - 1 < capacity) {
        const std::size_t subindex = object.entries.size();
        object.entries.push_back(make_entry(static_cast<std::uint8_t>(subindex), access,
                                            std::vector<std::uint8_t>(pdo_entry_size(object.kind), 0),
                                            pdo_entry_type(object.kind), subindex_name(subindex)));
    }
}

class DictionaryBuilder {
public:
    DictionaryBuilder(const EscDescription& description, const EscLayout& layout)
        : description_(description),
          layout_(layout),
          log_(logger("esc")),
          owner_(fmt::format("slave {:?}", description.name)) {}

    Objects build() {
        add_standard_objects();
        for (const auto& pdo : description_.process_data.rx_pdos) add_pdo(pdo, false);
        for (const auto& pdo : description_.process_data.tx_pdos) add_pdo(pdo, true);
        add_pdo_assignments();
        if (description_.mailbox) add_init_cmd_objects(description_.mailbox->coe_init_cmds);
        for (auto& [index, object] : objects_) {
            if (object.kind == ObjectKind::Record) set_count(object, object.entries.back().subindex);
        }
        return std::move(objects_);
    }

private:
    void add_standard_objects() {
        constexpr auto ro = EntryAccess::ReadOnly;
        add(variable(0x1000, "Device type", ro, little_endian(0, 4), coe_type::kUnsigned32));
        add(variable(0x1008, "Device name", ro, text(description_.name), coe_type::kVisibleString));
        add(variable(0x1009, "Manufacturer hardware version", ro, text("ecsim"), coe_type::kVisibleString));
        add(variable(0x100A, "Manufacturer software version", ro, text("ecsim"), coe_type::kVisibleString));
        DictionaryObject identity = with_count(0x1018, ObjectKind::Record, "Identity", ro);
        const std::uint32_t identity_values[] = {description_.vendor_id, description_.product_code,
                                                 description_.revision_no, description_.serial_no};
        const char* identity_names[] = {"Vendor ID", "Product code", "Revision", "Serial number"};
        for (std::uint8_t s = 1; s <= 4; ++s) {
            identity.entries.push_back(make_entry(s, ro, little_endian(identity_values[s - 1], 4), coe_type::kUnsigned32,
                                                  identity_names[s - 1]));
        }
        add(std::move(identity));
        if (layout_.described_sm_count > 0) {
            DictionaryObject types = with_count(0x1C00, ObjectKind::Record, "Sync manager communication type", ro);
            for (int n = 0; n < layout_.described_sm_count; ++n) {
                const auto role = static_cast<std::uint8_t>(layout_.sms[static_cast<std::size_t>(n)].role);
                types.entries.push_back(make_entry(static_cast<std::uint8_t>(n + 1), ro, {role}, coe_type::kUnsigned8,
                                                   subindex_name(static_cast<std::size_t>(n + 1))));
            }
            add(std::move(types));
        }
    }

    // The mapping object of `pdo` and the application objects it maps:
    // RxPDO objects are writable, TxPDO objects read-only.
    void add_pdo(const eni::Pdo& pdo, bool tx) {
        if (objects_.contains(pdo.index)) {
            log_->warn("{}: PDO {:#06x} is described twice; the first description is kept", owner_, pdo.index);
            return;
        }
        const EntryAccess access = pdo.fixed ? EntryAccess::ReadOnly : EntryAccess::ReadWriteInPreop;
        DictionaryObject mapping = with_count(pdo.index, ObjectKind::PdoMapping, pdo.name, access);
        for (const eni::PdoEntry& e : pdo.entries) {
            for (std::uint16_t left = e.bit_length; left > 0 && mapping.entries.size() <= kMaxEntries;) {
                const auto bits = std::min(left, kMaxMappedBits);
                const auto value =
                    static_cast<std::uint32_t>(e.index) << 16 | static_cast<std::uint32_t>(e.subindex) << 8 | bits;
                const std::size_t subindex = mapping.entries.size();
                mapping.entries.push_back(make_entry(static_cast<std::uint8_t>(subindex), access,
                                                     little_endian(value, kMappingEntrySize), coe_type::kUnsigned32,
                                                     subindex_name(subindex)));
                left = static_cast<std::uint16_t>(left - bits);
            }
            if (e.index != 0 && e.bit_length > 0) add_application_entry(e, tx);
        }
        set_count(mapping, mapping.entries.size() - 1);
        add(std::move(mapping));
    }

    void add_application_entry(const eni::PdoEntry& e, bool tx) {
        const EntryAccess access = tx ? EntryAccess::ReadOnly : EntryAccess::ReadWrite;
        const std::size_t size = (e.bit_length + 7u) / 8u;
        ObjectEntry described = make_entry(e.subindex, access, std::vector<std::uint8_t>(size, 0), mapped_type(e), e.name);
        described.bit_length = e.bit_length;
        auto it = objects_.find(e.index);
        if (it == objects_.end()) {
            if (e.subindex == 0) {
                add(DictionaryObject{e.index, ObjectKind::Variable, e.name, {described}});
            } else {
                add(with_count(e.index, ObjectKind::Record, e.name, EntryAccess::ReadOnly));
            }
            it = objects_.find(e.index);
        }
        DictionaryObject& object = it->second;
        if (object.kind == ObjectKind::Record && e.subindex != 0) entry_at(object, std::move(described));
        // Whichever PDOs map it say in which direction it is mappable.
        if (ObjectEntry* entry = object.entry(object.kind == ObjectKind::Variable ? 0 : e.subindex);
            entry != nullptr && (object.kind == ObjectKind::Variable || e.subindex != 0)) {
            (tx ? entry->tx_pdo_mappable : entry->rx_pdo_mappable) = true;
        }
    }

    void add_pdo_assignments() {
        for (std::size_t n = 0; n < layout_.sms.size(); ++n) {
            const SmRole role = layout_.sms[n].role;
            if (role != SmRole::Outputs && role != SmRole::Inputs) continue;
            const auto index = static_cast<std::uint16_t>(ObjectDictionary::kPdoAssignmentBase + n);
            DictionaryObject assignment = with_count(index, ObjectKind::PdoAssignment,
                                                     fmt::format("Sync manager {} PDO assignment", n),
                                                     EntryAccess::ReadWriteInPreop);
            std::size_t assigned = 0;
            for (const AssignedPdo& a : layout_.pdos) {
                if (a.sm != n || assigned == kMaxEntries - 1) continue;
                ++assigned;
                assignment.entries.push_back(make_entry(static_cast<std::uint8_t>(assigned), EntryAccess::ReadWriteInPreop,
                                                        little_endian(a.pdo->index, kAssignmentEntrySize),
                                                        coe_type::kUnsigned16, subindex_name(assigned)));
            }
            set_count(assignment, assigned);
            const auto& same_direction =
                role == SmRole::Outputs ? description_.process_data.rx_pdos : description_.process_data.tx_pdos;
            grow_pdo_object(assignment, same_direction.size());
            add(std::move(assignment));
        }
    }

    void add_init_cmd_objects(const std::vector<eni::CoeInitCmd>& cmds) {
        // Grouped by object first: whether an object is a record depends on all its commands.
        std::map<std::uint16_t, std::vector<const eni::CoeInitCmd*>> by_index;
        for (const auto& cmd : cmds) {
            if (!cmd.data.empty()) by_index[cmd.index].push_back(&cmd);
        }
        for (const auto& [index, writes] : by_index) {
            DictionaryObject& object = object_for(index, writes);
            for (const eni::CoeInitCmd* cmd : writes) {
                if (object.kind == ObjectKind::PdoMapping || object.kind == ObjectKind::PdoAssignment) {
                    make_room_for(object, *cmd);
                } else {
                    make_writable(object, *cmd);
                }
            }
        }
    }

    DictionaryObject& object_for(std::uint16_t index, const std::vector<const eni::CoeInitCmd*>& writes) {
        if (auto it = objects_.find(index); it != objects_.end()) return it->second;
        ObjectKind kind = kind_for_index(index);
        const bool any_subindex = std::any_of(writes.begin(), writes.end(),
                                              [](const eni::CoeInitCmd* c) { return c->subindex > 0 || c->complete_access; });
        if (kind == ObjectKind::Record && !any_subindex) kind = ObjectKind::Variable;
        log_->debug("{}: object {:#06x} created for the ENI's CoE InitCmds", owner_, index);
        if (kind == ObjectKind::Variable) {
            return add(variable(index, writes.front()->comment, EntryAccess::ReadWrite, {}, 0));
        }
        const EntryAccess count_access = kind == ObjectKind::Record ? EntryAccess::ReadOnly : EntryAccess::ReadWriteInPreop;
        return add(with_count(index, kind, writes.front()->comment, count_access));
    }

    // A mapping or assignment object written by an InitCmd: writable in
    // PREOP (even when the ENI calls the PDO fixed) and large enough.
    void make_room_for(DictionaryObject& object, const eni::CoeInitCmd& cmd) {
        for (ObjectEntry& entry : object.entries) entry.access = EntryAccess::ReadWriteInPreop;
        std::size_t needed = cmd.subindex;
        if (cmd.complete_access) {
            const std::size_t header = cmd.subindex == 0 ? kSubindexZeroOnWire : 0;
            const std::size_t first = cmd.subindex == 0 ? 1 : cmd.subindex;
            needed = first - 1 + (cmd.data.size() - std::min(header, cmd.data.size())) / pdo_entry_size(object.kind);
        }
        grow_pdo_object(object, needed);
    }

    // Any other object: the written subindex exists, with the written size, and is writable.
    void make_writable(DictionaryObject& object, const eni::CoeInitCmd& cmd) {
        if (cmd.complete_access) {
            log_->warn("{}: CompleteAccess InitCmd to {:#06x} (line {}): the entry sizes of this object are unknown, "
                       "so it is not pre-created and its download will abort", owner_, cmd.index, cmd.source_line);
            return;
        }
        if (object.kind == ObjectKind::Variable && cmd.subindex != 0) {
            log_->warn("{}: InitCmd to {:#06x}:{:02x} (line {}): the object is a single value", owner_, cmd.index,
                       cmd.subindex, cmd.source_line);
            return;
        }
        const bool is_count = object.kind == ObjectKind::Record && cmd.subindex == 0;
        const std::size_t size = is_count ? 1 : cmd.data.size();
        ObjectEntry& entry = entry_at(object, make_entry(cmd.subindex, EntryAccess::ReadWrite,
                                                         std::vector<std::uint8_t>(size, 0),
                                                         coe_data_type_of_size(size), cmd.comment));
        entry.access = EntryAccess::ReadWrite;
        if (entry.value.empty()) entry.value.resize(size);  // a Variable created by object_for
        if (entry.data_type == 0) entry.data_type = coe_data_type_of_size(entry.value.size());
        if (entry.value.size() != cmd.data.size()) {
            log_->warn("{}: InitCmd to {:#06x}:{:02x} (line {}) writes {} bytes, the entry has {}", owner_, cmd.index,
                       cmd.subindex, cmd.source_line, cmd.data.size(), entry.value.size());
        }
    }

    DictionaryObject& add(DictionaryObject object) {
        const std::uint16_t index = object.index;
        return objects_.insert_or_assign(index, std::move(object)).first->second;
    }

    const EscDescription& description_;
    const EscLayout& layout_;
    std::shared_ptr<spdlog::logger> log_;
    std::string owner_;
    Objects objects_;
};

}  // namespace

ObjectDictionary ObjectDictionary::for_slave(const EscDescription& description) {
    const EscLayout layout = EscLayout::of(description);
    return ObjectDictionary(DictionaryBuilder(description, layout).build());
}

}  // namespace ecpair::sim
