#pragma once
// The CANopen object dictionary of an emulated slave (ETG.1000.6 §5.6.7):
// what the CoE server reads and writes when a master uploads or downloads
// an SDO.
//
// for_slave() builds it from the slave's description (docs/ESC_EMULATION.md
// "CoE server" lists every object): the standard objects (0x1000, 0x1008,
// 0x1009, 0x100A, 0x1018, 0x1C00), the PDO mapping objects of the ENI's
// RxPDOs/TxPDOs, the PDO assignment objects 0x1C10+n of its process data
// SyncManagers, the application objects those PDOs map, and every object
// and subindex the ENI's CoE InitCmds write (with the written size), so that
// vendor objects only the real device knows still accept their InitCmds.
//
// Every entry has a fixed size and an access right. Downloads are checked
// the way a slave stack checks them and refused with an SDO abort code
// (wire::sdo_abort). PDO mapping and assignment objects follow the
// PDO configuration rules: writable in PREOP only, entries only while
// subindex 0 is 0 (or all at once with CompleteAccess).

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::sim {

struct EscDescription;

// An SDO abort code (wire::sdo_abort::k...): why an access was refused.
using SdoAbortCode = std::uint32_t;

enum class EntryAccess : std::uint8_t {
    ReadOnly,
    ReadWrite,         // in every state with a running mailbox
    ReadWriteInPreop,  // PDO configuration: refused (0x08000022) outside PREOP
};

enum class ObjectKind : std::uint8_t {
    Variable,       // a single value at subindex 0; no CompleteAccess
    Record,         // subindex 0 = highest subindex, then the entries
    PdoMapping,     // subindex 0 = entry count; entries UDINT index<<16 | subindex<<8 | bit length
    PdoAssignment,  // 0x1C10 + SyncManager; subindex 0 = PDO count; entries UINT PDO indices
};

struct ObjectEntry {
    std::uint8_t subindex = 0;
    EntryAccess access = EntryAccess::ReadOnly;
    std::vector<std::uint8_t> value;  // its size is the entry's size: a download must match it
    // What SDO Information describes (an entry description):
    std::uint16_t data_type = 0;   // CoE data type index (wire::coe_type)
    std::uint16_t bit_length = 0;  // 0: the value's size in bits
    std::string name;
    bool rx_pdo_mappable = false;  // an RxPDO of the ENI maps it
    bool tx_pdo_mappable = false;  // a TxPDO of the ENI maps it

    std::uint16_t bits() const { return bit_length != 0 ? bit_length : static_cast<std::uint16_t>(value.size() * 8); }
};

struct DictionaryObject {
    std::uint16_t index = 0;
    ObjectKind kind = ObjectKind::Variable;
    std::string name;
    std::vector<ObjectEntry> entries;  // ascending subindex; all but a Variable start with subindex 0

    const ObjectEntry* entry(std::uint8_t subindex) const;
    ObjectEntry* entry(std::uint8_t subindex);
};

// CompleteAccess carries subindex 0 (an 8-bit count) padded to 16 bits.
inline constexpr std::size_t kSubindexZeroOnWire = 2;

// Which object an SDO addresses, and how: one entry, or with CompleteAccess
// the whole object from subindex 0 (subindex 0 padded to 16 bits) or 1.
struct SdoAddress {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    bool complete_access = false;
};

class ObjectDictionary {
public:
    static constexpr std::uint16_t kPdoAssignmentBase = 0x1C10;

    // The dictionary of the slave `description` describes.
    static ObjectDictionary for_slave(const EscDescription& description);

    const DictionaryObject* find(std::uint16_t index) const;
    // Every object, in ascending index order (SDO Information's OD list).
    const std::map<std::uint16_t, DictionaryObject>& objects() const { return objects_; }

    // The bytes an upload returns.
    Expected<std::vector<std::uint8_t>, SdoAbortCode> upload(const SdoAddress& address) const;
    // Whether a download of `size` bytes would be accepted in `state`: what a
    // slave checks before it accepts the first part of a segmented transfer.
    Expected<void, SdoAbortCode> check_download(const SdoAddress& address, std::size_t size,
                                                eni::SlaveState state) const;
    // Checks and writes; nothing changes when it is refused.
    Expected<void, SdoAbortCode> download(const SdoAddress& address, ConstBytes data, eni::SlaveState state);

    // Whether writing this object changes what a SyncManager carries.
    static bool is_pdo_configuration(std::uint16_t index);
    // The SyncManagers that have a PDO assignment object (0x1C10 + n).
    std::vector<std::uint8_t> assigned_sync_managers() const;
    // Bytes of process data the PDOs assigned to SyncManager `sm` map, as a
    // slave stack computes the SM length it expects; nullopt when an assigned
    // PDO has no mapping object here.
    std::optional<std::uint16_t> process_data_bytes(std::uint8_t sm) const;

private:
    explicit ObjectDictionary(std::map<std::uint16_t, DictionaryObject> objects);

    // One entry a validated download writes, with its new value.
    struct PlannedWrite {
        std::uint8_t subindex = 0;
        ConstBytes bytes;
    };
    Expected<std::vector<PlannedWrite>, SdoAbortCode> plan_download(const SdoAddress& address, ConstBytes data,
                                                                    eni::SlaveState state) const;

    std::map<std::uint16_t, DictionaryObject> objects_;
};

}  // namespace ecpair::sim
