// The mailbox protocols besides SDO, byte for byte: FoE's six messages and
// its error texts, EoE's header and the IP parameters of a set-IP request
// (the Elmo EAS ENI's own InitCmd data), SoE's header and IDN names, and
// the CoE emergency.

#include <catch2/catch.hpp>

#include "ecpair/common/hex.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/eoe.hpp"
#include "ecpair/wire/foe.hpp"
#include "ecpair/wire/soe.hpp"

using namespace ecpair::wire;

namespace {

std::vector<std::uint8_t> bytes(std::initializer_list<int> values) {
    std::vector<std::uint8_t> out;
    for (const int v : values) out.push_back(static_cast<std::uint8_t>(v));
    return out;
}

}  // namespace

TEST_CASE("FoE: read and write requests carry the password and the file name", "[wire][foe]") {
    const auto rrq = encode_foe(FoeReadRequest{0x12345678, "app.bin"});
    CHECK(rrq == bytes({0x01, 0x00, 0x78, 0x56, 0x34, 0x12, 'a', 'p', 'p', '.', 'b', 'i', 'n'}));
    const auto back = decode_foe(rrq);
    REQUIRE(back);
    CHECK(std::get<FoeReadRequest>(*back) == FoeReadRequest{0x12345678, "app.bin"});

    const auto wrq = encode_foe(FoeWriteRequest{0, "fw"});
    CHECK(wrq == bytes({0x02, 0x00, 0, 0, 0, 0, 'f', 'w'}));
    // A NUL after the name (some slaves send one) ends it.
    auto with_nul = wrq;
    with_nul.push_back(0);
    with_nul.push_back('x');
    CHECK(std::get<FoeWriteRequest>(*decode_foe(with_nul)).file == "fw");
}

TEST_CASE("FoE: data, ack, error and busy", "[wire][foe]") {
    const auto data = encode_foe(FoeData{3, {0xAA, 0xBB}});
    CHECK(data == bytes({0x03, 0x00, 3, 0, 0, 0, 0xAA, 0xBB}));
    CHECK(std::get<FoeData>(*decode_foe(data)) == FoeData{3, {0xAA, 0xBB}});
    CHECK(std::get<FoeData>(*decode_foe(encode_foe(FoeData{9, {}}))).data.empty());

    CHECK(encode_foe(FoeAck{7}) == bytes({0x04, 0x00, 7, 0, 0, 0}));
    CHECK(std::get<FoeAck>(*decode_foe(bytes({0x04, 0x00, 7, 0, 0, 0}))).packet == 7);

    const auto error = encode_foe(FoeError{foe_error::kNotFound, "nope"});
    CHECK(error == bytes({0x05, 0x00, 0x01, 0x80, 0, 0, 'n', 'o', 'p', 'e'}));
    CHECK(std::get<FoeError>(*decode_foe(error)) == FoeError{0x8001, "nope"});
    CHECK(foe_error_text(foe_error::kNotFound) == "file not found");
    CHECK(foe_error_text(foe_error::kNoRights) == "no rights (wrong password)");
    CHECK(foe_error_text(0x1234) == "unknown FoE error");

    const auto busy = encode_foe(FoeBusy{5, 10, ""});
    CHECK(busy == bytes({0x06, 0x00, 5, 0, 10, 0}));
    CHECK(std::get<FoeBusy>(*decode_foe(busy)) == FoeBusy{5, 10, ""});
}

TEST_CASE("FoE: what is not an FoE message", "[wire][foe]") {
    CHECK_FALSE(decode_foe(bytes({0x01, 0x00, 0, 0, 0})));       // shorter than the header
    CHECK_FALSE(decode_foe(bytes({0x07, 0x00, 0, 0, 0, 0})));    // no OpCode 7
    CHECK_FALSE(decode_foe(bytes({0x00, 0x00, 0, 0, 0, 0})));
}

TEST_CASE("EoE: the header's bits", "[wire][eoe]") {
    EoeHeader h;
    h.type = EoeFrameType::SetIpResponse;
    h.port = 2;
    h.last_fragment = true;
    h.time_request = true;
    h.word = eoe_result::kNoIpSupport;
    std::vector<std::uint8_t> out(EoeHeader::kSize);
    h.encode(out);
    CHECK(out == bytes({0x23, 0x05, 0x01, 0x02}));
    const auto back = EoeHeader::decode(out);
    REQUIRE(back);
    CHECK(back->type == EoeFrameType::SetIpResponse);
    CHECK(back->port == 2);
    CHECK(back->last_fragment);
    CHECK_FALSE(back->time_appended);
    CHECK(back->time_request);
    CHECK(back->word == 0x0201);
    CHECK_FALSE(EoeHeader::decode(bytes({0x02, 0x01, 0x00})));
    CHECK(eoe_result_text(eoe_result::kNoIpSupport) == "no IP support");
}

TEST_CASE("EoE: the IP parameters of the Elmo EAS ENI's InitCmd", "[wire][eoe]") {
    // tests/data/eni/elmo_eas_rocos_1slave.xml, line 205.
    const auto data = ecpair::parse_hex(
        "3F00000010189EFF01040401A8C000FFFFFF0A01A8C000000000000000000000000000000000000000000000000000000000000000000000"
        "0000");
    REQUIRE(data);
    REQUIRE(data->size() == EoeIpParameters::kEncodedSize);
    const auto p = EoeIpParameters::decode(*data);
    REQUIRE(p);
    REQUIRE(p->ip);
    CHECK(ipv4_text(*p->ip) == "192.168.1.4");
    CHECK(ipv4_text(*p->subnet) == "255.255.255.0");
    CHECK(ipv4_text(*p->gateway) == "192.168.1.10");
    CHECK(p->dns_server == 0u);
    CHECK(p->dns_name == "");
    CHECK(p->mac->to_string() == "10:18:9e:ff:01:04");
    CHECK(p->describe() ==
          "IP 192.168.1.4, subnet 255.255.255.0, gateway 192.168.1.10, DNS server 0.0.0.0, DNS name '', MAC "
          "10:18:9e:ff:01:04");
    CHECK(p->encode() == *data);
}

TEST_CASE("EoE: only the fields the flags include, and cut-off ones refused", "[wire][eoe]") {
    EoeIpParameters p;
    p.ip = 0x0A000001;
    const auto out = p.encode();
    CHECK(out.size() == EoeIpParameters::kEncodedSize);
    CHECK(out[0] == 0x02);
    const auto back = EoeIpParameters::decode(out);
    REQUIRE(back);
    CHECK(*back == p);
    CHECK(back->describe() == "IP 10.0.0.1");
    CHECK(EoeIpParameters{}.describe() == "nothing");
    // IP included but the bytes end before it.
    CHECK_FALSE(EoeIpParameters::decode(bytes({0x02, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7})));
    CHECK_FALSE(EoeIpParameters::decode(bytes({0x02, 0})));
    // Nothing included: four bytes are enough.
    CHECK(EoeIpParameters::decode(bytes({0, 0, 0, 0})));
}

TEST_CASE("SoE: the header's bits and IDN names", "[wire][soe]") {
    SoeHeader h;
    h.opcode = SoeOpcode::WriteRequest;
    h.incomplete = true;
    h.drive = 5;
    h.elements = soe_elements::kValue;
    h.idn_or_fragments = 3;
    std::vector<std::uint8_t> out(SoeHeader::kSize);
    h.encode(out);
    CHECK(out == bytes({0xAB, 0x40, 0x03, 0x00}));
    const auto back = SoeHeader::decode(bytes({0x14, 0x40, 0x0F, 0x00}));
    REQUIRE(back);
    CHECK(back->opcode == SoeOpcode::WriteResponse);
    CHECK(back->error);
    CHECK_FALSE(back->incomplete);
    CHECK(back->drive == 0);
    CHECK(back->idn_or_fragments == 15);
    CHECK_FALSE(SoeHeader::decode(bytes({0x01, 0x40, 0x0F})));
    CHECK(idn_text(15) == "S-0-0015");
    CHECK(idn_text(0x8000 + 100) == "P-0-0100");
    CHECK(idn_text(0x1000 + 32) == "S-1-0032");
    CHECK(soe_error_text(0x1001) == "IDN not in the drive");
    CHECK(soe_error_text(0x4242) == "unknown SoE error");
}

TEST_CASE("CoE emergency: code, register and five bytes of data", "[wire][coe]") {
    const auto in = bytes({0x30, 0x81, 0x11, 1, 2, 3, 4, 5});
    const auto e = CoeEmergency::decode(in);
    REQUIRE(e);
    CHECK(e->error_code == 0x8130);
    CHECK(e->error_register == 0x11);
    CHECK(e->data == std::array<std::uint8_t, 5>{1, 2, 3, 4, 5});
    std::vector<std::uint8_t> out(CoeEmergency::kSize);
    e->encode(out);
    CHECK(out == in);
    CHECK_FALSE(CoeEmergency::decode(bytes({0x30, 0x81, 0x11, 1, 2, 3, 4})));
    CHECK(emergency_error_class(0x8130) == "communication");
    CHECK(emergency_error_class(0x4210) == "temperature");
    CHECK(emergency_error_class(0xA000) == "PREOP to SAFEOP transition failed");
    CHECK(emergency_error_class(0xFF01) == "device specific");
}
