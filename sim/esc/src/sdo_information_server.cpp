#include "sdo_information_server.hpp"

#include <algorithm>
#include <variant>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sim {
namespace {

namespace access = wire::object_access;
using wire::SdoInfoOpcode;

constexpr std::uint16_t kReadable = access::kReadPreop | access::kReadSafeop | access::kReadOp;

bool rx_mappable(const DictionaryObject& o) {
    return std::any_of(o.entries.begin(), o.entries.end(), [](const ObjectEntry& e) { return e.rx_pdo_mappable; });
}

bool tx_mappable(const DictionaryObject& o) {
    return std::any_of(o.entries.begin(), o.entries.end(), [](const ObjectEntry& e) { return e.tx_pdo_mappable; });
}

}  // namespace

SdoInformationServer::SdoInformationServer(const ObjectDictionary& dictionary, std::size_t fragment_capacity)
    : dictionary_(dictionary), capacity_(fragment_capacity & ~std::size_t{1}) {}

void SdoInformationServer::reset() {
    pending_ = false;
    response_.clear();
    sent_ = 0;
}

void SdoInformationServer::handle(ConstBytes request) {
    reset();
    const auto decoded = wire::decode_sdo_info_request(request);
    if (const auto* error = std::get_if<wire::SdoInfoDecodeError>(&decoded)) {
        logger("esc")->debug("SDO Information request refused at byte {}: {}", error->offset, error->what);
        return fail(wire::sdo_abort::kUnknownCommand);
    }
    const auto& r = std::get<wire::SdoInfoRequest>(decoded);
    if (const auto* list = std::get_if<wire::OdListRequest>(&r)) {
        bool known = false;
        auto data = od_list(list->list_type, known);
        if (!known) return fail(wire::sdo_abort::kUnsupportedAccess);
        return respond(SdoInfoOpcode::OdListResponse, std::move(data));
    }
    if (const auto* object = std::get_if<wire::ObjectDescriptionRequest>(&r)) {
        const DictionaryObject* found = dictionary_.find(object->index);
        if (found == nullptr) return fail(wire::sdo_abort::kObjectDoesNotExist);
        return respond(SdoInfoOpcode::ObjectDescriptionResponse, describe_object(*found).encode());
    }
    if (const auto* entry = std::get_if<wire::EntryDescriptionRequest>(&r)) {
        const DictionaryObject* found = dictionary_.find(entry->index);
        if (found == nullptr) return fail(wire::sdo_abort::kObjectDoesNotExist);
        const ObjectEntry* e = found->entry(entry->subindex);
        if (e == nullptr) return fail(wire::sdo_abort::kSubindexDoesNotExist);
        return respond(SdoInfoOpcode::EntryDescriptionResponse, describe_entry(*found, *e).encode());
    }
    // The master's SDO Info Error request: it gave up; nothing to answer.
}

std::vector<std::uint8_t> SdoInformationServer::od_list(wire::OdListType type, bool& known) const {
    wire::OdListResponse list;
    list.list_type = type;
    known = true;
    const auto& objects = dictionary_.objects();
    switch (type) {
        case wire::OdListType::Counts: {
            const auto count = [&](auto&& keep) {
                return static_cast<std::uint16_t>(
                    std::count_if(objects.begin(), objects.end(), [&](const auto& o) { return keep(o.second); }));
            };
            list.indices = {static_cast<std::uint16_t>(objects.size()), count(rx_mappable), count(tx_mappable), 0, 0};
            break;
        }
        case wire::OdListType::All:
        case wire::OdListType::RxPdoMappable:
        case wire::OdListType::TxPdoMappable:
            for (const auto& [index, object] : objects) {
                if (type == wire::OdListType::RxPdoMappable && !rx_mappable(object)) continue;
                if (type == wire::OdListType::TxPdoMappable && !tx_mappable(object)) continue;
                list.indices.push_back(index);
            }
            break;
        case wire::OdListType::Backup:
        case wire::OdListType::Settings: break;
        default: known = false; break;
    }
    return list.encode();
}

wire::ObjectDescription SdoInformationServer::describe_object(const DictionaryObject& object) const {
    wire::ObjectDescription d;
    d.index = object.index;
    d.name = object.name;
    d.max_subindex = object.entries.empty() ? 0 : object.entries.back().subindex;
    const std::uint16_t first_type = object.entries.size() > 1 ? object.entries[1].data_type : 0;
    switch (object.kind) {
        case ObjectKind::Variable:
            d.object_code = wire::kObjectCodeVariable;
            d.max_subindex = 0;
            d.data_type = object.entries.empty() ? 0 : object.entries.front().data_type;
            break;
        case ObjectKind::PdoMapping:
            d.object_code = wire::kObjectCodeRecord;
            d.data_type = wire::coe_type::kPdoMapping;
            break;
        case ObjectKind::PdoAssignment:
            d.object_code = wire::kObjectCodeArray;
            d.data_type = wire::coe_type::kUnsigned16;
            break;
        case ObjectKind::Record:
            d.object_code = object.index == 0x1C00 ? wire::kObjectCodeArray : wire::kObjectCodeRecord;
            d.data_type = object.index == 0x1018 ? wire::coe_type::kIdentity : first_type;
            break;
    }
    return d;
}

wire::EntryDescription SdoInformationServer::describe_entry(const DictionaryObject& object, const ObjectEntry& entry) const {
    wire::EntryDescription d;
    d.index = object.index;
    d.subindex = entry.subindex;
    d.data_type = entry.data_type;
    d.bit_length = entry.bits();
    d.object_access = kReadable;
    switch (entry.access) {
        case EntryAccess::ReadOnly: break;
        case EntryAccess::ReadWrite:
            d.object_access |= access::kWritePreop | access::kWriteSafeop | access::kWriteOp;
            break;
        case EntryAccess::ReadWriteInPreop: d.object_access |= access::kWritePreop; break;
    }
    if (entry.rx_pdo_mappable) d.object_access |= access::kRxPdoMappable;
    if (entry.tx_pdo_mappable) d.object_access |= access::kTxPdoMappable;
    d.name = entry.name;
    return d;
}

void SdoInformationServer::respond(SdoInfoOpcode opcode, std::vector<std::uint8_t> data) {
    opcode_ = opcode;
    response_ = std::move(data);
    sent_ = 0;
    pending_ = capacity_ > 0;
}

void SdoInformationServer::fail(std::uint32_t abort_code) {
    respond(SdoInfoOpcode::Error, wire::SdoInfoError{abort_code}.encode());
}

std::size_t SdoInformationServer::next_fragment(Bytes out) {
    if (!pending_) return 0;
    const std::size_t left = response_.size() - sent_;
    const std::size_t take = std::min(left, capacity_);
    const std::size_t after = left - take;
    const auto fragments_after = static_cast<std::uint16_t>((after + capacity_ - 1) / capacity_);
    wire::SdoInfoHeader{opcode_, after > 0, fragments_after}.encode(out);
    std::copy_n(response_.begin() + static_cast<std::ptrdiff_t>(sent_), take, out.begin() + wire::SdoInfoHeader::kSize);
    sent_ += take;
    pending_ = after > 0;
    return wire::SdoInfoHeader::kSize + take;
}

}  // namespace ecpair::sim
