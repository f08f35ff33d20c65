// CoE SDO Information (issue 11, item 4): an independent master walks the
// object dictionary with Get OD List, Get Object Description and Get Entry
// Description, as SOEM's ecx_readODlist / ecx_readODdescription /
// ecx_readOE do: a request into SM0, then every fragment of the response
// out of SM1 until one comes without the "incomplete" bit.

#include <algorithm>
#include <filesystem>
#include <optional>
#include <variant>

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "esc_test_support.hpp"
#include "soem_sii_reader.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::SdoInfoOpcode;

namespace {

constexpr std::uint16_t kStation = kFirstStation;

struct Fragment {
    wire::SdoInfoHeader header;
    std::vector<std::uint8_t> data;
};

struct Response {
    SdoInfoOpcode opcode = SdoInfoOpcode::Error;
    std::vector<Fragment> fragments;
    std::vector<std::uint8_t> data;  // the fragments' service data joined
};

// A slave in PREOP, its mailbox SyncManagers configured from its SII as
// SOEM does; `in_length` shrinks SM1 (0: as the description says).
class InfoMaster {
public:
    explicit InfoMaster(EscDescription description, std::uint16_t in_length = 0)
        : line_({with_mailbox_in(std::move(description), in_length)}) {
        line_.assign_station_addresses();
        SoemSiiReader sii(line_, kStation);
        const auto sms = sii.sync_managers();
        REQUIRE(sms.size() >= 2);
        out_ = {sms[0].start, sms[0].length};
        in_ = {sms[1].start, sms[1].length};
        std::vector<std::uint8_t> config;
        for (const auto& sm : {sms[0], sms[1]}) {
            for (auto b : le16(sm.start)) config.push_back(b);
            for (auto b : le16(sm.length)) config.push_back(b);
            for (auto b : bytes({sm.control, 0x00, 0x01, 0x00})) config.push_back(b);
        }
        REQUIRE(line_.fpwr(kStation, 0x0800, config) == 1);
        REQUIRE(line_.fpwr(kStation, 0x0120, le16(0x0002)) == 1);
        REQUIRE(line_.fprd(kStation, 0x0130, 1)[0] == 0x02);
    }

    void send(const wire::SdoInfoRequest& request) {
        const auto info = wire::encode_sdo_info_request(request);
        std::vector<std::uint8_t> message(8, 0);
        counter_ = wire::next_mailbox_counter(counter_);
        wire::MailboxHeader{static_cast<std::uint16_t>(2 + info.size()), 0, 0, 0, wire::MailboxType::CoE, counter_}.encode(message);
        wire::CoeHeader{0, wire::CoeService::SdoInformation}.encode(Bytes(message).subspan(6));
        message.insert(message.end(), info.begin(), info.end());
        message.resize(out_.length, 0);
        REQUIRE(line_.fpwr(kStation, out_.start, message) == 1);
    }

    // One SM1 reply, if the slave put one there.
    std::optional<Fragment> read_fragment() {
        if ((line_.fprd(kStation, 0x080D, 1)[0] & 0x08) == 0) return std::nullopt;
        const auto d = line_.transact(physical_read(wire::Command::Fprd, kStation, in_.start, in_.length));
        REQUIRE(d.wkc == 1);
        const auto header = wire::MailboxHeader::decode(d.data);
        REQUIRE(header);
        CHECK(header->address == kStation);
        REQUIRE(header->type == wire::MailboxType::CoE);
        const ConstBytes body = ConstBytes(d.data).subspan(wire::MailboxHeader::kSize, header->length);
        const auto coe = wire::CoeHeader::decode(body);
        REQUIRE(coe);
        REQUIRE(coe->service == wire::CoeService::SdoInformation);
        const auto info = wire::SdoInfoHeader::decode(body.subspan(2));
        REQUIRE(info);
        const auto data = body.subspan(2 + wire::SdoInfoHeader::kSize);
        return Fragment{*info, {data.begin(), data.end()}};
    }

    Response exchange(const wire::SdoInfoRequest& request) {
        send(request);
        Response r;
        for (;;) {
            auto fragment = read_fragment();
            REQUIRE(fragment);
            r.opcode = fragment->header.opcode;
            r.data.insert(r.data.end(), fragment->data.begin(), fragment->data.end());
            const bool last = !fragment->header.incomplete;
            r.fragments.push_back(std::move(*fragment));
            if (last) return r;
            REQUIRE(r.fragments.size() < 1000);
        }
    }

    std::vector<std::uint16_t> od_list(wire::OdListType type) {
        const auto r = exchange(wire::OdListRequest{type});
        REQUIRE(r.opcode == SdoInfoOpcode::OdListResponse);
        const auto list = wire::OdListResponse::decode(r.data);
        REQUIRE(list);
        CHECK(list->list_type == type);
        return list->indices;
    }
    std::variant<wire::ObjectDescription, std::uint32_t> object(std::uint16_t index) {
        const auto r = exchange(wire::ObjectDescriptionRequest{index});
        if (r.opcode == SdoInfoOpcode::Error) return wire::SdoInfoError::decode(r.data).value().abort_code;
        REQUIRE(r.opcode == SdoInfoOpcode::ObjectDescriptionResponse);
        return wire::ObjectDescription::decode(r.data).value();
    }
    std::variant<wire::EntryDescription, std::uint32_t> entry(std::uint16_t index, std::uint8_t subindex) {
        const auto r = exchange(wire::EntryDescriptionRequest{index, subindex, 0});
        if (r.opcode == SdoInfoOpcode::Error) return wire::SdoInfoError::decode(r.data).value().abort_code;
        REQUIRE(r.opcode == SdoInfoOpcode::EntryDescriptionResponse);
        return wire::EntryDescription::decode(r.data).value();
    }

    Line& line() { return line_; }

private:
    static EscDescription with_mailbox_in(EscDescription d, std::uint16_t in_length) {
        if (in_length != 0) {
            d.mailbox->recv->length = in_length;
            d.mailbox->bootstrap_recv = d.mailbox->recv;
        }
        return d;
    }

    Line line_;
    eni::MailboxArea out_;
    eni::MailboxArea in_;
    std::uint8_t counter_ = 0;
};

// drive_description() maps 0x6040 (UINT) and 0x607A (DINT) in RxPDO 0x1600,
// 0x6041, 0x6064, 0x6061 in TxPDO 0x1A00 (docs of esc_test_support.hpp).
const std::vector<std::uint16_t> kDriveObjects = {0x1000, 0x1008, 0x1009, 0x100A, 0x1018, 0x1600, 0x1A00,
                                                  0x1C00, 0x1C12, 0x1C13, 0x6040, 0x6041, 0x6061, 0x6064, 0x607A};

}  // namespace

TEST_CASE("the SII CoE details advertise SDO, SDO Information, PDO assignment/configuration and CompleteAccess") {
    Line line({drive_description(), io_description()});
    line.assign_station_addresses();
    SoemSiiReader drive(line, kStation);
    const std::uint32_t general = drive.find(30);
    REQUIRE(general != 0);
    CHECK(drive.byte(general + 2 + 5) == 0x2F);  // the general category's byte 5: CoE details
    SoemSiiReader io(line, kStation + 1);
    const std::uint32_t io_general = io.find(30);
    REQUIRE(io_general != 0);
    CHECK(io.byte(io_general + 2 + 5) == 0x00);  // no mailbox, no CoE
}

TEST_CASE("Get OD List: every object in index order, and the counts per list type") {
    InfoMaster m(drive_description());
    CHECK(m.od_list(wire::OdListType::All) == kDriveObjects);
    CHECK(m.od_list(wire::OdListType::RxPdoMappable) == std::vector<std::uint16_t>{0x6040, 0x607A});
    CHECK(m.od_list(wire::OdListType::TxPdoMappable) == std::vector<std::uint16_t>{0x6041, 0x6061, 0x6064});
    CHECK(m.od_list(wire::OdListType::Backup).empty());
    CHECK(m.od_list(wire::OdListType::Counts) ==
          std::vector<std::uint16_t>{static_cast<std::uint16_t>(kDriveObjects.size()), 2, 3, 0, 0});
}

TEST_CASE("a response longer than SM1 comes in fragments, each with the fragments left after it") {
    // SM1 of 32 bytes: 6 mailbox + 2 CoE + 4 SDO Info header leave 20 bytes.
    InfoMaster m(drive_description(), 32);
    m.send(wire::OdListRequest{wire::OdListType::All});
    std::vector<Fragment> fragments;
    std::vector<std::uint8_t> joined;
    while (auto f = m.read_fragment()) {
        joined.insert(joined.end(), f->data.begin(), f->data.end());
        fragments.push_back(std::move(*f));
        if (!fragments.back().header.incomplete) break;
    }
    const std::size_t bytes = 2 + 2 * kDriveObjects.size();  // list type + indices
    REQUIRE(fragments.size() == (bytes + 19) / 20);
    for (std::size_t i = 0; i < fragments.size(); ++i) {
        INFO("fragment " << i);
        CHECK(fragments[i].header.opcode == SdoInfoOpcode::OdListResponse);
        CHECK(fragments[i].header.incomplete == (i + 1 < fragments.size()));
        CHECK(fragments[i].header.fragments_left == fragments.size() - 1 - i);
        CHECK(fragments[i].data.size() % 2 == 0);  // never cut inside an index
        CHECK(fragments[i].data.size() <= 20);
    }
    CHECK(wire::OdListResponse::decode(joined).value().indices == kDriveObjects);
    CHECK_FALSE(m.read_fragment());
}

TEST_CASE("a new request drops the fragments still to come") {
    InfoMaster m(drive_description(), 32);
    m.send(wire::OdListRequest{wire::OdListType::All});
    const auto first = m.read_fragment();
    REQUIRE(first);
    REQUIRE(first->header.incomplete);
    // Reading SM1 let the slave post the second fragment at once; the new
    // request finds it there, so its answer waits behind it, and nothing
    // more of the list follows.
    m.send(wire::ObjectDescriptionRequest{0x1018});
    const auto second = m.read_fragment();
    REQUIRE(second);
    CHECK(second->header.opcode == SdoInfoOpcode::OdListResponse);
    CHECK(second->header.fragments_left == first->header.fragments_left - 1);
    const auto answer = m.read_fragment();
    REQUIRE(answer);
    CHECK(answer->header.opcode == SdoInfoOpcode::ObjectDescriptionResponse);
    CHECK(wire::ObjectDescription::decode(answer->data).value().name == "Identity");
    CHECK_FALSE(m.read_fragment());
    // The master's own SDO Info Error request is not answered.
    m.send(wire::SdoInfoErrorRequest{wire::sdo_abort::kGeneralError});
    CHECK_FALSE(m.read_fragment());
}

TEST_CASE("Get Object Description: object code, data type, highest subindex and name") {
    InfoMaster m(drive_description());
    const auto object = [&](std::uint16_t index) {
        auto r = m.object(index);
        REQUIRE(std::holds_alternative<wire::ObjectDescription>(r));
        auto d = std::get<wire::ObjectDescription>(r);
        CHECK(d.index == index);
        return d;
    };
    const auto identity = object(0x1018);
    CHECK(identity.object_code == wire::kObjectCodeRecord);
    CHECK(identity.data_type == wire::coe_type::kIdentity);
    CHECK(identity.max_subindex == 4);
    const auto name = object(0x1008);
    CHECK(name.object_code == wire::kObjectCodeVariable);
    CHECK(name.data_type == wire::coe_type::kVisibleString);
    CHECK(name.name == "Device name");
    const auto mapping = object(0x1600);
    CHECK(mapping.object_code == wire::kObjectCodeRecord);
    CHECK(mapping.data_type == wire::coe_type::kPdoMapping);
    CHECK(mapping.max_subindex == 2);
    const auto assignment = object(0x1C12);
    CHECK(assignment.object_code == wire::kObjectCodeArray);
    CHECK(assignment.data_type == wire::coe_type::kUnsigned16);
    const auto controlword = object(0x6040);
    CHECK(controlword.object_code == wire::kObjectCodeVariable);
    CHECK(controlword.data_type == wire::coe_type::kUnsigned16);
    const auto missing = m.object(0x5555);
    REQUIRE(std::holds_alternative<std::uint32_t>(missing));
    CHECK(std::get<std::uint32_t>(missing) == wire::sdo_abort::kObjectDoesNotExist);
}

TEST_CASE("Get Entry Description: data type, bit length, access in each state, PDO mapping, name") {
    InfoMaster m(drive_description());
    const auto entry = [&](std::uint16_t index, std::uint8_t subindex) {
        auto r = m.entry(index, subindex);
        REQUIRE(std::holds_alternative<wire::EntryDescription>(r));
        auto d = std::get<wire::EntryDescription>(r);
        CHECK(d.index == index);
        CHECK(d.subindex == subindex);
        return d;
    };
    namespace access = wire::object_access;
    const auto vendor = entry(0x1018, 1);
    CHECK(vendor.data_type == wire::coe_type::kUnsigned32);
    CHECK(vendor.bit_length == 32);
    CHECK(vendor.object_access == (access::kReadPreop | access::kReadSafeop | access::kReadOp));
    CHECK(vendor.name == "Vendor ID");
    const auto controlword = entry(0x6040, 0);
    CHECK(controlword.data_type == wire::coe_type::kUnsigned16);
    CHECK(controlword.bit_length == 16);
    CHECK(controlword.object_access == 0x3F + access::kRxPdoMappable);  // read and write in every state
    const auto statusword = entry(0x6041, 0);
    CHECK(statusword.object_access == 0x07 + access::kTxPdoMappable);
    const auto assigned = entry(0x1C12, 1);
    CHECK(assigned.data_type == wire::coe_type::kUnsigned16);
    CHECK(assigned.object_access == (0x07 | access::kWritePreop));  // PDO configuration: PREOP only
    const auto count = entry(0x1600, 0);
    CHECK(count.data_type == wire::coe_type::kUnsigned8);
    CHECK(count.bit_length == 8);
    const auto missing = m.entry(0x1018, 9);
    REQUIRE(std::holds_alternative<std::uint32_t>(missing));
    CHECK(std::get<std::uint32_t>(missing) == wire::sdo_abort::kSubindexDoesNotExist);
}

TEST_CASE("a BOOL entry of a digital PDO is described with its 1 bit") {
    EscDescription d = drive_description();
    eni::PdoEntry bit;
    bit.index = 0x7000;
    bit.subindex = 1;
    bit.bit_length = 1;
    bit.name = "Output 1";
    bit.data_type = "BOOL";
    d.process_data.rx_pdos.at(0).entries.push_back(bit);
    InfoMaster m(d);
    const auto r = m.entry(0x7000, 1);
    REQUIRE(std::holds_alternative<wire::EntryDescription>(r));
    CHECK(std::get<wire::EntryDescription>(r).data_type == wire::coe_type::kBoolean);
    CHECK(std::get<wire::EntryDescription>(r).bit_length == 1);
    CHECK(std::get<wire::EntryDescription>(r).name == "Output 1");
}

TEST_CASE("an independent master walks the whole dictionary of every CoE slave of every shared ENI") {
    std::size_t slaves = 0;
    std::size_t entries = 0;
    for (const auto& file : std::filesystem::directory_iterator(ECPAIR_TEST_ENI_DIR)) {
        if (file.path().extension() != ".xml") continue;
        const auto loaded = eni::load_eni_file(file.path().string());
        REQUIRE(loaded.has_value());
        for (const auto& slave : loaded.value()->slaves) {
            if (!slave.mailbox || !slave.mailbox->send || !slave.mailbox->recv) continue;
            auto description = EscDescription::from_eni(slave);
            if ((description.mailbox->protocols & eni::kCoE) == 0 && description.mailbox->coe_init_cmds.empty()) continue;
            INFO(file.path().filename().string() << ": " << slave.info.name);
            InfoMaster m(description);
            const auto all = m.od_list(wire::OdListType::All);
            REQUIRE_FALSE(all.empty());
            CHECK(std::is_sorted(all.begin(), all.end()));
            CHECK(std::find(all.begin(), all.end(), 0x1018) != all.end());
            for (const std::uint16_t index : all) {
                INFO("object 0x" << std::hex << index);
                const auto object = m.object(index);
                REQUIRE(std::holds_alternative<wire::ObjectDescription>(object));
                const auto& o = std::get<wire::ObjectDescription>(object);
                for (unsigned s = 0; s <= o.max_subindex; ++s) {
                    const auto e = m.entry(index, static_cast<std::uint8_t>(s));
                    if (!std::holds_alternative<wire::EntryDescription>(e)) continue;  // a record may have gaps
                    const auto& described = std::get<wire::EntryDescription>(e);
                    CHECK(described.data_type != 0);
                    CHECK(described.bit_length > 0);
                    CHECK((described.object_access & 0x07) == 0x07);
                    ++entries;
                }
            }
            ++slaves;
        }
    }
    CHECK(slaves >= 20);
    CHECK(entries >= 500);
}
