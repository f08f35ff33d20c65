// Access to the object dictionary. A download is planned first and
// committed only when every check passed:
//
//   1. which entries it covers: one entry, or with CompleteAccess the
//      entries from subindex 0 or 1 on, in subindex order, as many as the
//      data reaches (subindex 0 takes 16 bits on the wire). Read-only
//      entries inside a CompleteAccess stream are skipped, as SOES does;
//   2. the access rights of those entries in the current AL state and the
//      length of the data;
//   3. the PDO configuration rules for mapping and assignment objects:
//      subindex 0 (the count) at most the number of entries, the entries
//      writable one by one only while the count is 0, and an assigned PDO
//      must be a PDO mapping index (unused entries may hold 0).

#include "ecpair/sim/object_dictionary.hpp"

#include <algorithm>

#include "ecpair/wire/coe.hpp"

namespace ecpair::sim {
namespace {

namespace sdo_abort = wire::sdo_abort;

constexpr std::uint16_t kPdoAssignmentLast = 0x1C2F;

bool is_pdo_mapping_index(std::uint16_t index) {
    return (index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF);
}

bool is_pdo_object(const DictionaryObject& object) {
    return object.kind == ObjectKind::PdoMapping || object.kind == ObjectKind::PdoAssignment;
}

// Subindex 0 of a record, mapping or assignment object.
std::uint8_t count_of(const DictionaryObject& object) { return object.entries.front().value.front(); }

// Entries after subindex 0: PDO objects keep them dense (1..capacity).
std::size_t capacity_of(const DictionaryObject& object) { return object.entries.size() - 1; }

std::size_t wire_size(const ObjectEntry& entry, bool complete_access) {
    return complete_access && entry.subindex == 0 ? kSubindexZeroOnWire : entry.value.size();
}

Expected<void, SdoAbortCode> write_permission(const ObjectEntry& entry, eni::SlaveState state) {
    switch (entry.access) {
        case EntryAccess::ReadOnly: return unexpected(sdo_abort::kReadOnly);
        case EntryAccess::ReadWrite: return {};
        case EntryAccess::ReadWriteInPreop:
            if (state != eni::SlaveState::Preop) return unexpected(sdo_abort::kCannotStoreInState);
            return {};
    }
    return unexpected(sdo_abort::kGeneralError);
}

Expected<void, SdoAbortCode> length_matches(std::size_t carried, std::size_t expected) {
    if (carried > expected) return unexpected(sdo_abort::kLengthTooHigh);
    if (carried < expected) return unexpected(sdo_abort::kLengthTooLow);
    return {};
}

// One entry a download writes and where its bytes start in the data.
struct CoveredEntry {
    const ObjectEntry* entry = nullptr;
    std::size_t offset = 0;
};

// Steps 1 and 2 for a download of `size` bytes.
Expected<std::vector<CoveredEntry>, SdoAbortCode> covered_entries(const DictionaryObject& object,
                                                                 const SdoAddress& address, std::size_t size,
                                                                 eni::SlaveState state) {
    if (!address.complete_access) {
        const ObjectEntry* entry = object.entry(address.subindex);
        if (entry == nullptr) return unexpected(sdo_abort::kSubindexDoesNotExist);
        if (auto allowed = write_permission(*entry, state); !allowed) return unexpected(allowed.error());
        if (auto length = length_matches(size, entry->value.size()); !length) return unexpected(length.error());
        return std::vector<CoveredEntry>{{entry, 0}};
    }
    if (object.kind == ObjectKind::Variable || address.subindex > 1) {
        return unexpected(sdo_abort::kCompleteAccessUnsupported);
    }
    if (object.entry(address.subindex) == nullptr) return unexpected(sdo_abort::kSubindexDoesNotExist);
    if (size == 0) return unexpected(sdo_abort::kLengthTooLow);

    std::vector<CoveredEntry> covered;
    std::size_t offset = 0;
    bool read_only_skipped = false;
    for (const ObjectEntry& entry : object.entries) {
        if (entry.subindex < address.subindex) continue;
        if (offset == size) break;
        const std::size_t length = wire_size(entry, true);
        if (offset + length > size) return unexpected(sdo_abort::kLengthMismatch);  // ends inside an entry
        if (auto allowed = write_permission(entry, state); allowed) {
            covered.push_back({&entry, offset});
        } else if (allowed.error() == sdo_abort::kReadOnly) {
            read_only_skipped = true;
        } else {
            return unexpected(allowed.error());
        }
        offset += length;
    }
    if (offset < size) return unexpected(sdo_abort::kLengthTooHigh);
    if (covered.empty() && read_only_skipped) return unexpected(sdo_abort::kReadOnly);
    return covered;
}

}  // namespace

const ObjectEntry* DictionaryObject::entry(std::uint8_t subindex) const {
    const auto it = std::find_if(entries.begin(), entries.end(),
                                 [subindex](const ObjectEntry& e) { return e.subindex == subindex; });
    return it == entries.end() ? nullptr : &*it;
}

ObjectEntry* DictionaryObject::entry(std::uint8_t subindex) {
    return const_cast<ObjectEntry*>(std::as_const(*this).entry(subindex));
}

ObjectDictionary::ObjectDictionary(std::map<std::uint16_t, DictionaryObject> objects) : objects_(std::move(objects)) {}

const DictionaryObject* ObjectDictionary::find(std::uint16_t index) const {
    const auto it = objects_.find(index);
    return it == objects_.end() ? nullptr : &it->second;
}

Expected<std::vector<std::uint8_t>, SdoAbortCode> ObjectDictionary::upload(const SdoAddress& address) const {
    const DictionaryObject* object = find(address.index);
    if (object == nullptr) return unexpected(sdo_abort::kObjectDoesNotExist);
    if (address.complete_access && (object->kind == ObjectKind::Variable || address.subindex > 1)) {
        return unexpected(sdo_abort::kCompleteAccessUnsupported);
    }
    const ObjectEntry* first = object->entry(address.subindex);
    if (first == nullptr) return unexpected(sdo_abort::kSubindexDoesNotExist);
    if (!address.complete_access) return first->value;

    std::vector<std::uint8_t> stream;
    for (const ObjectEntry& entry : object->entries) {
        if (entry.subindex < address.subindex) continue;
        stream.insert(stream.end(), entry.value.begin(), entry.value.end());
        if (entry.subindex == 0) stream.push_back(0);  // the padding byte
    }
    return stream;
}

Expected<void, SdoAbortCode> ObjectDictionary::check_download(const SdoAddress& address, std::size_t size,
                                                              eni::SlaveState state) const {
    const DictionaryObject* object = find(address.index);
    if (object == nullptr) return unexpected(sdo_abort::kObjectDoesNotExist);
    auto covered = covered_entries(*object, address, size, state);
    if (!covered) return unexpected(covered.error());
    return {};
}

Expected<std::vector<ObjectDictionary::PlannedWrite>, SdoAbortCode> ObjectDictionary::plan_download(
    const SdoAddress& address, ConstBytes data, eni::SlaveState state) const {
    const DictionaryObject* object = find(address.index);
    if (object == nullptr) return unexpected(sdo_abort::kObjectDoesNotExist);
    auto covered = covered_entries(*object, address, data.size(), state);
    if (!covered) return unexpected(covered.error());

    std::vector<PlannedWrite> writes;
    for (const CoveredEntry& c : *covered) {
        writes.push_back({c.entry->subindex, data.subspan(c.offset, c.entry->value.size())});
    }
    if (!is_pdo_object(*object)) return writes;

    // Step 3: the PDO configuration rules.
    const auto is_count = [](const PlannedWrite& w) { return w.subindex == 0; };
    const auto count_write = std::find_if(writes.begin(), writes.end(), is_count);
    const std::uint8_t new_count = count_write != writes.end() ? count_write->bytes.front() : count_of(*object);
    if (new_count > capacity_of(*object)) return unexpected(sdo_abort::kValueOutOfRange);
    const bool writes_entries = !std::all_of(writes.begin(), writes.end(), is_count);
    if (writes_entries && count_write == writes.end() && count_of(*object) != 0) {
        return unexpected(sdo_abort::kSubindexZeroNotZero);
    }
    if (object->kind == ObjectKind::PdoAssignment) {
        for (const PlannedWrite& w : writes) {
            if (w.subindex == 0) continue;
            const auto pdo = load_le<std::uint16_t>(w.bytes);
            const bool unused = pdo == 0 && w.subindex > new_count;
            if (!unused && !is_pdo_mapping_index(pdo)) return unexpected(sdo_abort::kValueOutOfRange);
        }
    }
    return writes;
}

Expected<void, SdoAbortCode> ObjectDictionary::download(const SdoAddress& address, ConstBytes data,
                                                        eni::SlaveState state) {
    auto writes = plan_download(address, data, state);
    if (!writes) return unexpected(writes.error());
    DictionaryObject& object = objects_.at(address.index);
    for (const PlannedWrite& w : *writes) {
        ObjectEntry* entry = object.entry(w.subindex);
        std::copy(w.bytes.begin(), w.bytes.end(), entry->value.begin());
    }
    return {};
}

bool ObjectDictionary::is_pdo_configuration(std::uint16_t index) {
    return is_pdo_mapping_index(index) || (index >= kPdoAssignmentBase && index <= kPdoAssignmentLast);
}

std::vector<std::uint8_t> ObjectDictionary::assigned_sync_managers() const {
    std::vector<std::uint8_t> sms;
    for (auto it = objects_.lower_bound(kPdoAssignmentBase); it != objects_.end() && it->first <= kPdoAssignmentLast; ++it) {
        if (it->second.kind == ObjectKind::PdoAssignment) {
            sms.push_back(static_cast<std::uint8_t>(it->first - kPdoAssignmentBase));
        }
    }
    return sms;
}

std::optional<std::uint16_t> ObjectDictionary::process_data_bytes(std::uint8_t sm) const {
    const DictionaryObject* assignment = find(static_cast<std::uint16_t>(kPdoAssignmentBase + sm));
    if (assignment == nullptr || assignment->kind != ObjectKind::PdoAssignment) return std::nullopt;
    std::uint32_t bits = 0;
    for (std::size_t n = 1; n <= count_of(*assignment); ++n) {
        const auto pdo = load_le<std::uint16_t>(assignment->entries[n].value);
        const DictionaryObject* mapping = find(pdo);
        if (mapping == nullptr || mapping->kind != ObjectKind::PdoMapping) return std::nullopt;
        for (std::size_t m = 1; m <= count_of(*mapping); ++m) {
            bits += mapping->entries[m].value.front();  // the low byte of the entry: its bit length
        }
    }
    const std::uint32_t bytes = (bits + 7) / 8;
    if (bytes > 0xFFFF) return std::nullopt;
    return static_cast<std::uint16_t>(bytes);
}

}  // namespace ecpair::sim
