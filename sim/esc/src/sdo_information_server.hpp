#pragma once
// The SDO Information service of the CoE server (ETG.1000.6 §5.6.3): a
// master walks the object dictionary with Get OD List, Get Object
// Description and Get Entry Description; the answers come from the
// ObjectDictionary the CoE server serves SDOs from.
//
// handle() prepares the whole response (or an SDO Info Error: 0x06020000 no
// such object, 0x06090011 no such subindex, 0x06010000 an OD list type the
// slave does not know, 0x05040001 a request it cannot decode); the CoE
// server then takes it fragment by fragment with next_fragment(), one per
// mailbox reply, each no longer than the capacity it was built with (an
// even number of bytes, so an OD list is never cut inside an index). A
// master's SDO Info Error request, or any new request, drops what is left.
//
// What the dictionary describes: object code VAR (7) for single values,
// ARRAY (8) for PDO assignments and 0x1C00, RECORD (9) otherwise; data type
// 0x0021 PDO_MAPPING / 0x0023 IDENTITY / the entries' type; every entry
// readable in PREOP, SAFEOP and OP, writable as its access says, RxPDO /
// TxPDO mappable when the ENI's PDOs map it; no unit, default, minimum or
// maximum (value info 0). No object is flagged for backup or settings.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/sim/object_dictionary.hpp"
#include "ecpair/wire/sdo_information.hpp"

namespace ecpair::sim {

class SdoInformationServer {
public:
    // `fragment_capacity`: the service data bytes one reply can carry after
    // the mailbox, CoE and SDO Info headers.
    SdoInformationServer(const ObjectDictionary& dictionary, std::size_t fragment_capacity);

    // `request` starts after the CoE header.
    void handle(ConstBytes request);
    bool has_fragment() const { return pending_; }
    // SDO Info header and service data of the next fragment into `out`
    // (at least SdoInfoHeader::kSize + capacity bytes); its size.
    std::size_t next_fragment(Bytes out);
    void reset();

    std::size_t fragment_capacity() const { return capacity_; }

private:
    void respond(wire::SdoInfoOpcode opcode, std::vector<std::uint8_t> data);
    void fail(std::uint32_t abort_code);
    std::vector<std::uint8_t> od_list(wire::OdListType type, bool& known) const;
    wire::ObjectDescription describe_object(const DictionaryObject& object) const;
    wire::EntryDescription describe_entry(const DictionaryObject& object, const ObjectEntry& entry) const;

    const ObjectDictionary& dictionary_;
    std::size_t capacity_;
    wire::SdoInfoOpcode opcode_ = wire::SdoInfoOpcode::Error;
    std::vector<std::uint8_t> response_;  // the service data of the whole response
    std::size_t sent_ = 0;                // bytes of response_ already sent
    bool pending_ = false;
};

}  // namespace ecpair::sim
