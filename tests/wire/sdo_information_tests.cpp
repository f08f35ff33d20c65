// SDO Information codec: the bytes SOEM's ec_SDOservicet layout puts on the
// wire (opcode with the incomplete bit, reserved byte, fragments left, then
// the service data), both directions, and what a request that cannot be
// decoded is refused for.

#include <variant>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/wire/sdo_information.hpp"

using namespace ecpair;
using namespace ecpair::wire;

TEST_CASE("SDO Information requests encode as SOEM sends them and decode back") {
    CHECK(encode_sdo_info_request(OdListRequest{OdListType::All}) == std::vector<std::uint8_t>{0x01, 0, 0, 0, 0x01, 0x00});
    CHECK(encode_sdo_info_request(ObjectDescriptionRequest{0x1018}) ==
          std::vector<std::uint8_t>{0x03, 0, 0, 0, 0x18, 0x10});
    CHECK(encode_sdo_info_request(EntryDescriptionRequest{0x1A00, 2, 0x08}) ==
          std::vector<std::uint8_t>{0x05, 0, 0, 0, 0x00, 0x1A, 0x02, 0x08});
    for (const SdoInfoRequest& r : {SdoInfoRequest{OdListRequest{OdListType::TxPdoMappable}},
                                    SdoInfoRequest{ObjectDescriptionRequest{0x6041}},
                                    SdoInfoRequest{EntryDescriptionRequest{0x1018, 4, 0}},
                                    SdoInfoRequest{SdoInfoErrorRequest{0x06020000}}}) {
        const auto decoded = decode_sdo_info_request(encode_sdo_info_request(r));
        REQUIRE(std::holds_alternative<SdoInfoRequest>(decoded));
        CHECK(std::get<SdoInfoRequest>(decoded) == r);
    }
}

TEST_CASE("SDO Information requests that cannot be decoded say why and where") {
    const auto error = [](std::vector<std::uint8_t> bytes) {
        const auto decoded = decode_sdo_info_request(bytes);
        REQUIRE(std::holds_alternative<SdoInfoDecodeError>(decoded));
        return std::get<SdoInfoDecodeError>(decoded);
    };
    CHECK(error({0x01, 0}).what == "shorter than the 4-byte SDO Information header");
    const auto short_entry = error({0x05, 0, 0, 0, 0x18, 0x10, 0x01});
    CHECK(short_entry.offset == 7);
    CHECK(short_entry.what == "Get Entry Description request shorter than index, subindex and value info");
    CHECK(error({0x81, 0, 1, 0, 1, 0}).what == "a fragmented request (no request is longer than one mailbox)");
    CHECK(error({0x04, 0, 0, 0, 0x18, 0x10}).what == "opcode 4 is not a request");
}

TEST_CASE("the header carries the incomplete bit and the fragments left") {
    std::vector<std::uint8_t> out(4);
    SdoInfoHeader{SdoInfoOpcode::OdListResponse, true, 0x0102}.encode(out);
    CHECK(out == std::vector<std::uint8_t>{0x82, 0x00, 0x02, 0x01});
    const auto back = SdoInfoHeader::decode(out);
    REQUIRE(back);
    CHECK(back->opcode == SdoInfoOpcode::OdListResponse);
    CHECK(back->incomplete);
    CHECK(back->fragments_left == 0x0102);
}

TEST_CASE("responses round-trip, and an entry description skips unit and default/min/max before its name") {
    const OdListResponse list{OdListType::All, {0x1000, 0x1018, 0x6041}};
    CHECK(list.encode() == std::vector<std::uint8_t>{0x01, 0x00, 0x00, 0x10, 0x18, 0x10, 0x41, 0x60});
    CHECK(OdListResponse::decode(list.encode()).value().indices == list.indices);
    CHECK_FALSE(OdListResponse::decode(std::vector<std::uint8_t>{0x01, 0x00, 0x18}));  // half an index

    const ObjectDescription object{0x1018, coe_type::kIdentity, 4, kObjectCodeRecord, "Identity"};
    const auto object_back = ObjectDescription::decode(object.encode());
    REQUIRE(object_back);
    CHECK(object_back->name == "Identity");
    CHECK(object_back->max_subindex == 4);
    CHECK(object_back->object_code == kObjectCodeRecord);

    const EntryDescription entry{0x6041, 0, 0, coe_type::kUnsigned16, 16, 0x0087, "Statusword"};
    const auto entry_back = EntryDescription::decode(entry.encode());
    REQUIRE(entry_back);
    CHECK(entry_back->bit_length == 16);
    CHECK(entry_back->object_access == 0x0087);
    CHECK(entry_back->name == "Statusword");
    // A slave that sends unit (4 bytes) and a default value (2 bytes) before the name.
    std::vector<std::uint8_t> with_values = {0x41, 0x60, 0x00, 0x18, 0x06, 0x00, 0x10, 0x00, 0x87, 0x00,
                                             0xAA, 0xBB, 0xCC, 0xDD, 0x01, 0x02, 'S', 'W', 0x00};
    CHECK(EntryDescription::decode(with_values).value().name == "SW");

    CHECK(SdoInfoError::decode(SdoInfoError{0x06090011}.encode()).value().abort_code == 0x06090011);
}
