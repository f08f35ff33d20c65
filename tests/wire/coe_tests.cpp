// Mailbox and CoE SDO codec: command specifiers checked against the
// constants masters use on the wire (expedited download 0x23 | (4-n)<<2,
// normal download with CompleteAccess 0x31, upload request 0x40/0x50,
// download response 0x60, segments, abort 0x80).

#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/mailbox.hpp"

using namespace ecpair::wire;

namespace {

std::vector<std::uint8_t> encode(const SdoMessage& m) {
    std::vector<std::uint8_t> out(m.encoded_size());
    m.encode(out);
    return out;
}

}  // namespace

TEST_CASE("mailbox header fields and their bytes", "[wire][mailbox]") {
    MailboxHeader h{10, 0x03e9, 0, 0, MailboxType::CoE, 5};
    std::vector<std::uint8_t> out(MailboxHeader::kSize + 10);
    h.encode(out);
    CHECK(std::vector<std::uint8_t>(out.begin(), out.begin() + 6) == std::vector<std::uint8_t>{0x0a, 0x00, 0xe9, 0x03, 0x00, 0x53});
    auto back = MailboxHeader::decode(out);
    REQUIRE(back);
    CHECK(*back == h);
    CHECK_FALSE(MailboxHeader::decode(std::vector<std::uint8_t>(out.begin(), out.begin() + 12)));  // length past the end
    CHECK_FALSE(MailboxHeader::decode(std::vector<std::uint8_t>(4)));
    CHECK(next_mailbox_counter(7) == 1);
    CHECK(next_mailbox_counter(0) == 1);
    CHECK(next_mailbox_counter(3) == 4);
}

TEST_CASE("expedited download of one byte", "[wire][coe]") {
    SdoMessage m;
    m.command = SdoCommand::Download;
    m.expedited = true;
    m.index = 0x1c12;
    m.subindex = 0;
    m.data = {0x00};
    CHECK(encode(m) == std::vector<std::uint8_t>{0x2f, 0x12, 0x1c, 0x00, 0x00, 0x00, 0x00, 0x00});
    auto back = SdoMessage::decode(encode(m), false);
    REQUIRE(back);
    CHECK(back->command == SdoCommand::Download);
    CHECK(back->expedited);
    CHECK(back->data == std::vector<std::uint8_t>{0x00});

    m.data = {0x01, 0x02, 0x03, 0x04};
    CHECK(encode(m)[0] == 0x23);
}

TEST_CASE("normal download with CompleteAccess", "[wire][coe]") {
    SdoMessage m;
    m.command = SdoCommand::Download;
    m.complete_access = true;
    m.index = 0x1c12;
    m.subindex = 0;
    m.data = {0x01, 0x00, 0x02, 0x16};  // 1 entry: 0x1602
    m.complete_size = 4;
    m.expedited = false;
    const auto bytes = encode(m);
    CHECK(bytes == std::vector<std::uint8_t>{0x31, 0x12, 0x1c, 0x00, 0x04, 0x00, 0x00, 0x00, 0x01, 0x00, 0x02, 0x16});
    auto back = SdoMessage::decode(bytes, false);
    REQUIRE(back);
    CHECK(back->complete_access);
    CHECK_FALSE(back->expedited);
    CHECK(back->complete_size == 4);
    CHECK(back->data == m.data);
}

TEST_CASE("upload request, expedited and normal upload responses", "[wire][coe]") {
    SdoMessage req;
    req.command = SdoCommand::Upload;
    req.index = 0x1018;
    req.subindex = 1;
    CHECK(encode(req) == std::vector<std::uint8_t>{0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0});
    req.complete_access = true;
    CHECK(encode(req)[0] == 0x50);

    const std::vector<std::uint8_t> expedited = {0x43, 0x18, 0x10, 0x01, 0x9a, 0x00, 0x00, 0x00};
    auto r = SdoMessage::decode(expedited, true);
    REQUIRE(r);
    CHECK(r->command == SdoCommand::Upload);
    CHECK(r->is_response);
    CHECK(r->expedited);
    CHECK(r->data == std::vector<std::uint8_t>{0x9a, 0x00, 0x00, 0x00});

    const std::vector<std::uint8_t> two_bytes = {0x4b, 0x00, 0x10, 0x00, 0x92, 0x01, 0x00, 0x00};
    CHECK(SdoMessage::decode(two_bytes, true)->data == std::vector<std::uint8_t>{0x92, 0x01});

    const std::vector<std::uint8_t> normal = {0x41, 0x08, 0x10, 0x00, 0x03, 0x00, 0x00, 0x00, 'a', 'b', 'c'};
    auto n = SdoMessage::decode(normal, true);
    REQUIRE(n);
    CHECK_FALSE(n->expedited);
    CHECK(n->complete_size == 3);
    CHECK(n->data == std::vector<std::uint8_t>{'a', 'b', 'c'});
}

TEST_CASE("download response and abort", "[wire][coe]") {
    SdoMessage resp;
    resp.command = SdoCommand::Download;
    resp.is_response = true;
    resp.index = 0x1c12;
    CHECK(encode(resp) == std::vector<std::uint8_t>{0x60, 0x12, 0x1c, 0x00, 0, 0, 0, 0});
    auto back = SdoMessage::decode(encode(resp), true);
    REQUIRE(back);
    CHECK(back->command == SdoCommand::Download);

    const auto abort = encode(SdoMessage::abort(0x6060, 0, sdo_abort::kObjectDoesNotExist));
    CHECK(abort == std::vector<std::uint8_t>{0x80, 0x60, 0x60, 0x00, 0x00, 0x00, 0x02, 0x06});
    auto a = SdoMessage::decode(abort, true);
    REQUIRE(a);
    CHECK(a->command == SdoCommand::Abort);
    CHECK(a->complete_size == sdo_abort::kObjectDoesNotExist);
    CHECK(sdo_abort_text(a->complete_size) == "object does not exist in the object dictionary");
}

TEST_CASE("segments: toggle, last flag, short last segment", "[wire][coe]") {
    SdoMessage seg;
    seg.command = SdoCommand::DownloadSegment;
    seg.toggle = true;
    seg.last_segment = true;
    seg.data = {1, 2, 3};
    const auto bytes = encode(seg);
    REQUIRE(bytes.size() == 8);
    CHECK(bytes[0] == (0x10 | (4 << 1) | 0x01));
    auto back = SdoMessage::decode(bytes, false);
    REQUIRE(back);
    CHECK(back->toggle);
    CHECK(back->last_segment);
    CHECK(back->data == std::vector<std::uint8_t>{1, 2, 3});

    SdoMessage up;
    up.command = SdoCommand::UploadSegment;
    CHECK(encode(up)[0] == 0x60);
    up.is_response = true;
    up.data.assign(20, 7);
    const auto long_segment = encode(up);
    CHECK(long_segment.size() == 21);
    CHECK(SdoMessage::decode(long_segment, true)->data.size() == 20);
}

TEST_CASE("malformed SDO messages are rejected, not read past", "[wire][coe]") {
    CHECK_FALSE(SdoMessage::decode({}, false));
    CHECK_FALSE(SdoMessage::decode(std::vector<std::uint8_t>{0x2f, 0x12}, false));
    CHECK_FALSE(SdoMessage::decode(std::vector<std::uint8_t>{0xe0, 0, 0, 0, 0, 0, 0, 0}, false));  // cs 7
    CHECK_FALSE(SdoMessage::decode(std::vector<std::uint8_t>{0x00, 1, 2}, false));  // segment too short
    // A normal transfer announcing fewer bytes than it carries keeps only the announced ones.
    auto m = SdoMessage::decode(std::vector<std::uint8_t>{0x21, 0, 0x20, 0, 2, 0, 0, 0, 9, 9, 9}, false);
    REQUIRE(m);
    CHECK(m->data.size() == 2);
}

TEST_CASE("CoE header", "[wire][coe]") {
    std::vector<std::uint8_t> out(2);
    CoeHeader{0, CoeService::SdoRequest}.encode(out);
    CHECK(out == std::vector<std::uint8_t>{0x00, 0x20});
    auto h = CoeHeader::decode(std::vector<std::uint8_t>{0x00, 0x30});
    REQUIRE(h);
    CHECK(h->service == CoeService::SdoResponse);
}
