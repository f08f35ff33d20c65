// The CoE server of the emulated slaves, driven like a master drives a
// slave: FPWR of a request into SM0, FPRD of the SM1 status (mailbox full),
// then FPRD of SM1. Covers every SDO transfer form, the abort
// codes, the mailbox header rules (counter, errors), the PDO configuration
// and its effect on the SAFEOP check, and every CoE InitCmd of every
// shared ENI.

#include <filesystem>
#include <numeric>
#include <optional>
#include <string>

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "esc_test_support.hpp"
#include "soem_sii_reader.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;
using wire::SdoCommand;
using wire::SdoMessage;
namespace sdo_abort = wire::sdo_abort;

namespace {

constexpr std::uint16_t kStation = kFirstStation;
constexpr std::uint8_t kPreop = 0x02;
constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kError = 0x10;

// Where a slave's standard mailbox is.
struct MailboxAreas {
    std::uint16_t out_start = 0x1000;
    std::uint16_t out_length = 128;
    std::uint16_t in_start = 0x1080;
    std::uint16_t in_length = 128;
};

struct Reply {
    wire::MailboxHeader header;
    std::vector<std::uint8_t> body;  // after the mailbox header, `header.length` bytes
};

// Requests as a master builds them.
SdoMessage upload_request(std::uint16_t index, std::uint8_t subindex, bool complete_access = false) {
    SdoMessage m;
    m.command = SdoCommand::Upload;
    m.index = index;
    m.subindex = subindex;
    m.complete_access = complete_access;
    return m;
}

SdoMessage upload_segment(bool toggle) {
    SdoMessage m;
    m.command = SdoCommand::UploadSegment;
    m.toggle = toggle;
    return m;
}

// Expedited when the data fits the command (and no CompleteAccess), else
// normal with `first_part` of `complete_size` bytes.
SdoMessage download_request(std::uint16_t index, std::uint8_t subindex, std::vector<std::uint8_t> first_part,
                            std::size_t complete_size, bool complete_access = false) {
    SdoMessage m;
    m.command = SdoCommand::Download;
    m.index = index;
    m.subindex = subindex;
    m.complete_access = complete_access;
    m.expedited = !complete_access && !first_part.empty() && complete_size <= 4;
    m.size_indicated = true;
    m.complete_size = static_cast<std::uint32_t>(complete_size);
    m.data = std::move(first_part);
    return m;
}

SdoMessage download_segment(bool toggle, bool last, std::vector<std::uint8_t> data) {
    SdoMessage m;
    m.command = SdoCommand::DownloadSegment;
    m.toggle = toggle;
    m.last_segment = last;
    m.data = std::move(data);
    return m;
}

// The master side of one slave's mailbox, and an SDO client on top of it
// that transfers expedited, normal or segmented like SOEM does.
class MailboxMaster {
public:
    MailboxMaster(Line& line, std::uint16_t station, MailboxAreas areas) : line_(line), station_(station), areas_(areas) {}

    // Writes a whole message (mailbox header first) into SM0.
    void write(std::vector<std::uint8_t> message) {
        message.resize(areas_.out_length, 0);
        REQUIRE(line_.fpwr(station_, areas_.out_start, message) == 1);
    }

    // SM1 when the slave marked it full.
    std::optional<Reply> read() {
        if ((line_.fprd(station_, 0x080D, 1)[0] & 0x08) == 0) return std::nullopt;
        const Datagram d = line_.transact(physical_read(Command::Fprd, station_, areas_.in_start, areas_.in_length));
        REQUIRE(d.wkc == 1);
        const auto header = wire::MailboxHeader::decode(d.data);
        REQUIRE(header);
        return Reply{*header, std::vector<std::uint8_t>(d.data.begin() + 6, d.data.begin() + 6 + header->length)};
    }

    std::vector<std::uint8_t> coe_message(const SdoMessage& sdo, std::uint8_t counter) const {
        std::vector<std::uint8_t> message(8 + sdo.encoded_size(), 0);
        wire::MailboxHeader{static_cast<std::uint16_t>(2 + sdo.encoded_size()), 0, 0, 0, wire::MailboxType::CoE, counter}
            .encode(message);
        wire::CoeHeader{0, wire::CoeService::SdoRequest}.encode(Bytes(message).subspan(6));
        sdo.encode(Bytes(message).subspan(8));
        return message;
    }

    std::uint8_t next_counter() { return counter_ = wire::next_mailbox_counter(counter_); }

    // One SDO request and its SDO reply (an abort included).
    SdoMessage exchange(const SdoMessage& request) {
        write(coe_message(request, next_counter()));
        const auto reply = read();
        REQUIRE(reply);
        REQUIRE(reply->header.type == wire::MailboxType::CoE);
        CHECK(reply->header.address == station_);
        const auto coe = wire::CoeHeader::decode(reply->body);
        REQUIRE(coe);
        auto sdo = SdoMessage::decode(ConstBytes(reply->body).subspan(2), true);
        REQUIRE(sdo);
        CHECK(coe->service == (sdo->command == SdoCommand::Abort ? wire::CoeService::SdoRequest
                                                                 : wire::CoeService::SdoResponse));
        return *sdo;
    }

    Expected<void, std::uint32_t> download(std::uint16_t index, std::uint8_t subindex, const std::vector<std::uint8_t>& data,
                                           bool complete_access = false) {
        const bool expedited = !complete_access && !data.empty() && data.size() <= 4;
        const std::size_t first = expedited ? data.size() : std::min<std::size_t>(data.size(), areas_.out_length - 16);
        const SdoMessage initiate = download_request(
            index, subindex, {data.begin(), data.begin() + static_cast<std::ptrdiff_t>(first)}, data.size(), complete_access);
        const SdoMessage response = exchange(initiate);
        if (response.command == SdoCommand::Abort) return unexpected(response.complete_size);
        REQUIRE(response.command == SdoCommand::Download);
        CHECK(response.index == index);
        CHECK(response.subindex == subindex);
        bool toggle = false;
        for (std::size_t offset = first; offset < data.size(); toggle = !toggle) {
            const std::size_t length = std::min<std::size_t>(areas_.out_length - 9, data.size() - offset);
            const SdoMessage segment =
                download_segment(toggle, offset + length == data.size(),
                                 {data.begin() + static_cast<std::ptrdiff_t>(offset),
                                  data.begin() + static_cast<std::ptrdiff_t>(offset + length)});
            const SdoMessage answer = exchange(segment);
            if (answer.command == SdoCommand::Abort) return unexpected(answer.complete_size);
            REQUIRE(answer.command == SdoCommand::DownloadSegment);
            CHECK(answer.toggle == toggle);
            offset += length;
        }
        return {};
    }

    Expected<std::vector<std::uint8_t>, std::uint32_t> upload(std::uint16_t index, std::uint8_t subindex,
                                                             bool complete_access = false) {
        const SdoMessage initiate = upload_request(index, subindex, complete_access);
        const SdoMessage response = exchange(initiate);
        if (response.command == SdoCommand::Abort) return unexpected(response.complete_size);
        REQUIRE(response.command == SdoCommand::Upload);
        CHECK(response.index == index);
        CHECK(response.subindex == subindex);
        CHECK(response.complete_access == complete_access);
        if (response.expedited) return response.data;
        std::vector<std::uint8_t> data = response.data;
        bool toggle = false;
        segments_of_last_upload_ = 0;
        while (data.size() < response.complete_size) {
            const SdoMessage request = upload_segment(toggle);
            const SdoMessage segment = exchange(request);
            if (segment.command == SdoCommand::Abort) return unexpected(segment.complete_size);
            REQUIRE(segment.command == SdoCommand::UploadSegment);
            CHECK(segment.toggle == toggle);
            data.insert(data.end(), segment.data.begin(), segment.data.end());
            ++segments_of_last_upload_;
            CHECK(segment.last_segment == (data.size() >= response.complete_size));
            if (segment.last_segment) break;
            toggle = !toggle;
        }
        CHECK(data.size() == response.complete_size);
        return data;
    }

    int segments_of_last_upload() const { return segments_of_last_upload_; }

private:
    Line& line_;
    std::uint16_t station_;
    MailboxAreas areas_;
    std::uint8_t counter_ = 0;
    int segments_of_last_upload_ = 0;
};

template <class T>
std::uint32_t abort_code(const Expected<T, std::uint32_t>& result) {
    return result ? 0 : result.error();
}

std::vector<std::uint8_t> counting(std::size_t n, std::uint8_t start = 1) {
    std::vector<std::uint8_t> out(n);
    std::iota(out.begin(), out.end(), start);
    return out;
}

eni::CoeInitCmd init_cmd(std::uint16_t index, std::uint8_t subindex, std::vector<std::uint8_t> data) {
    eni::CoeInitCmd cmd;
    cmd.index = index;
    cmd.subindex = subindex;
    cmd.data = std::move(data);
    return cmd;
}

// drive_description() with InitCmds that make vendor objects of 20 and 300
// bytes and a vendor record.
EscDescription coe_drive() {
    EscDescription d = drive_description();
    d.mailbox->coe_init_cmds = {init_cmd(0x2000, 0, counting(20)), init_cmd(0x2001, 0, counting(300)),
                                init_cmd(0x2002, 0, {2}), init_cmd(0x2002, 2, {0, 0})};
    return d;
}

struct Slave {
    Line line;
    MailboxMaster master;

    explicit Slave(EscDescription description, MailboxAreas areas = {})
        : line({std::move(description)}), master(line, kStation, areas) {
        line.assign_station_addresses();
    }
    Slave(const Slave&) = delete;  // `master` refers to `line`
    Slave& operator=(const Slave&) = delete;

    std::uint8_t request_state(std::uint16_t control) {
        REQUIRE(line.fpwr(kStation, 0x0120, le16(control)) == 1);
        return line.fprd(kStation, 0x0130, 1)[0];
    }
    std::uint16_t status_code() {
        const auto raw = line.fprd(kStation, 0x0134, 2);
        return static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
    }
    // SM2 (outputs at 0x1100) and SM3 (8 bytes of inputs at 0x1180) as the master configures them.
    void configure_process_data(std::uint16_t output_length) {
        auto sm2 = le16(0x1100);
        for (auto b : le16(output_length)) sm2.push_back(b);
        for (auto b : bytes({0x64, 0x00, output_length > 0 ? 1 : 0, 0x00})) sm2.push_back(b);
        REQUIRE(line.fpwr(kStation, 0x0810, sm2) == 1);
        REQUIRE(line.fpwr(kStation, 0x0818, bytes({0x80, 0x11, 0x08, 0x00, 0x20, 0x00, 0x01, 0x00})) == 1);
    }
};

struct DriveInPreop : Slave {
    explicit DriveInPreop(EscDescription description = coe_drive()) : Slave(std::move(description)) {
        REQUIRE(bring_drive_to(line, kStation, kPreop) == kPreop);
    }
};

std::vector<std::uint8_t> mailbox_message(wire::MailboxType type, std::uint16_t length, std::uint8_t counter,
                                          const std::vector<std::uint8_t>& body) {
    std::vector<std::uint8_t> message(6, 0);
    wire::MailboxHeader{length, 0, 0, 0, type, counter}.encode(message);
    message.insert(message.end(), body.begin(), body.end());
    return message;
}

std::uint16_t mailbox_error_of(const Reply& reply) {
    REQUIRE(reply.header.type == wire::MailboxType::Error);
    const auto error = wire::MailboxErrorReply::decode(reply.body);
    REQUIRE(error);
    return error->detail;
}

}  // namespace

TEST_CASE("a CoE slave answers uploads of its standard objects, with its station address and counting replies") {
    DriveInPreop slave;
    auto& m = slave.master;

    m.write(m.coe_message(upload_request(0x1018, 1), m.next_counter()));
    const auto reply = m.read();
    REQUIRE(reply);
    CHECK(reply->header.address == kStation);
    CHECK(reply->header.type == wire::MailboxType::CoE);
    CHECK(reply->header.counter == 1);
    const auto sdo = SdoMessage::decode(ConstBytes(reply->body).subspan(2), true);
    REQUIRE(sdo);
    CHECK(sdo->expedited);
    CHECK(sdo->data == le32(0x0000009A));

    CHECK(m.upload(0x1018, 0).value() == bytes({4}));
    CHECK(m.upload(0x1018, 2).value() == le32(0x00030924));
    CHECK(m.upload(0x1018, 3).value() == le32(0x00010420));
    CHECK(m.upload(0x1018, 4).value() == le32(0x00C0FFEE));
    std::vector<std::uint8_t> identity = {4, 0};
    for (const std::uint32_t v : {0x9AU, 0x00030924U, 0x00010420U, 0x00C0FFEEU}) {
        for (auto b : le32(v)) identity.push_back(b);
    }
    CHECK(m.upload(0x1018, 0, true).value() == identity);
    CHECK(m.upload(0x1018, 1, true).value() == std::vector<std::uint8_t>(identity.begin() + 2, identity.end()));

    CHECK(m.upload(0x1000, 0).value() == le32(0));
    CHECK(m.upload(0x1008, 0).value() == std::vector<std::uint8_t>{'d', 'r', 'i', 'v', 'e'});
    CHECK(m.upload(0x1009, 0).value() == std::vector<std::uint8_t>{'e', 'c', 's', 'i', 'm'});
    CHECK(m.upload(0x1C00, 0, true).value() == bytes({4, 0, 1, 2, 3, 4}));  // mbx out, mbx in, outputs, inputs
    CHECK(m.upload(0x1C12, 1).value() == le16(0x1600));
    CHECK(m.upload(0x1A00, 0).value() == bytes({4}));
    CHECK(m.upload(0x1A00, 1).value() == le32(0x60410010));
    CHECK(m.upload(0x1A00, 4).value() == le32(0x00000008));  // the gap
    CHECK(m.upload(0x6041, 0).value() == le16(0));            // an application object a PDO maps

}

TEST_CASE("replies count 1 to 7, then 1 again") {
    DriveInPreop slave;
    auto& m = slave.master;
    std::vector<int> counters;
    for (int i = 0; i < 8; ++i) {
        m.write(m.coe_message(upload_request(0x1000, 0), m.next_counter()));
        const auto reply = m.read();
        REQUIRE(reply);
        counters.push_back(reply->header.counter);
    }
    CHECK(counters == std::vector<int>{1, 2, 3, 4, 5, 6, 7, 1});
}

TEST_CASE("expedited, normal and segmented downloads and uploads carry the bytes exactly") {
    DriveInPreop slave;
    auto& m = slave.master;

    SECTION("expedited: up to 4 bytes in the command") {
        REQUIRE(m.download(0x6040, 0, le16(0x000F)));
        CHECK(m.upload(0x6040, 0).value() == le16(0x000F));
        REQUIRE(m.download(0x607A, 0, le32(0xDEADBEEF)));
        CHECK(m.upload(0x607A, 0).value() == le32(0xDEADBEEF));
    }
    SECTION("normal: 20 bytes in one message each way") {
        const auto data = counting(20, 100);
        REQUIRE(m.download(0x2000, 0, data));
        CHECK(m.upload(0x2000, 0).value() == data);
        CHECK(m.segments_of_last_upload() == 0);
    }
    SECTION("segmented: 300 bytes through mailboxes of 128") {
        const auto data = counting(300, 7);
        REQUIRE(m.download(0x2001, 0, data));  // 112 bytes, then segments of 119 and 69
        CHECK(m.upload(0x2001, 0).value() == data);
        CHECK(m.segments_of_last_upload() == 2);  // 112 bytes in the initiate reply, then 119 and 69
    }
    SECTION("a segmented upload with short last segment: padded to 7 bytes, saying how many are unused") {
        const auto data = counting(300, 7);
        REQUIRE(m.download(0x2001, 0, data));
        const SdoMessage first = m.exchange(upload_request(0x2001, 0));
        CHECK(first.complete_size == 300);
        CHECK(first.data.size() == 112);
        const SdoMessage second = m.exchange(upload_segment(false));
        CHECK(second.data.size() == 119);
        CHECK_FALSE(second.last_segment);
        const SdoMessage third = m.exchange(upload_segment(true));
        CHECK(third.data == std::vector<std::uint8_t>(data.begin() + 231, data.end()));
        CHECK(third.last_segment);
        CHECK(third.toggle);
    }
}

TEST_CASE("CompleteAccess writes subindex 0 and the entries in one transfer and reads the whole object") {
    DriveInPreop slave;
    auto& m = slave.master;

    // "0100 0016" style: subindex 0 = 1 (padded to 16 bits), then the entries.
    REQUIRE(m.download(0x1C12, 0, bytes({0x01, 0x00, 0x00, 0x16}), true));
    CHECK(m.upload(0x1C12, 0).value() == bytes({1}));
    CHECK(m.upload(0x1C12, 0, true).value() == bytes({0x01, 0x00, 0x00, 0x16}));

    std::vector<std::uint8_t> mapping = {0x01, 0x00};
    for (auto b : le32(0x60400010)) mapping.push_back(b);
    for (auto b : le32(0x607A0020)) mapping.push_back(b);
    REQUIRE(m.download(0x1600, 0, mapping, true));  // writes a shorter object than there is room for
    CHECK(m.upload(0x1600, 0).value() == bytes({1}));
    CHECK(m.upload(0x1600, 2).value() == le32(0x607A0020));
    CHECK(m.upload(0x1600, 0, true).value() == mapping);

    // From subindex 1: the entries only, allowed while subindex 0 is 0.
    CHECK(abort_code(m.download(0x1600, 1, le32(0x60400010), true)) == sdo_abort::kSubindexZeroNotZero);
    REQUIRE(m.download(0x1600, 0, bytes({0})));
    REQUIRE(m.download(0x1600, 1, counting(8), true));
    CHECK(m.upload(0x1600, 1, true).value() == counting(8));
    CHECK(m.upload(0x1600, 0).value() == bytes({0}));
}

TEST_CASE("every refusal gets its SDO abort code") {
    DriveInPreop slave;
    auto& m = slave.master;

    SECTION("object does not exist: 0x06020000") {
        CHECK(abort_code(m.download(0x2FFF, 0, bytes({1}))) == sdo_abort::kObjectDoesNotExist);
        CHECK(abort_code(m.upload(0x2FFF, 0)) == sdo_abort::kObjectDoesNotExist);
    }
    SECTION("subindex does not exist: 0x06090011") {
        CHECK(abort_code(m.upload(0x1018, 5)) == sdo_abort::kSubindexDoesNotExist);
        CHECK(abort_code(m.download(0x2002, 1, le16(1))) == sdo_abort::kSubindexDoesNotExist);  // a gap
        CHECK(abort_code(m.download(0x6040, 1, le16(1))) == sdo_abort::kSubindexDoesNotExist);
    }
    SECTION("length: too high 0x06070012, too low 0x06070013, not matching the entries 0x06070010") {
        CHECK(abort_code(m.download(0x6040, 0, bytes({1, 2, 3}))) == sdo_abort::kLengthTooHigh);
        CHECK(abort_code(m.download(0x6040, 0, bytes({1}))) == sdo_abort::kLengthTooLow);
        CHECK(abort_code(m.download(0x2000, 0, counting(21))) == sdo_abort::kLengthTooHigh);
        CHECK(abort_code(m.download(0x2001, 0, counting(301))) == sdo_abort::kLengthTooHigh);  // refused before the segments
        CHECK(abort_code(m.download(0x1600, 0, bytes({1, 0, 0x10, 0x00, 0x40}), true)) == sdo_abort::kLengthMismatch);
        CHECK(abort_code(m.download(0x1600, 0, std::vector<std::uint8_t>(2 + 4 * 3, 0), true)) == sdo_abort::kLengthTooHigh);
        CHECK(m.upload(0x6040, 0).value() == le16(0));  // nothing was written
    }
    SECTION("read only: 0x06010002") {
        CHECK(abort_code(m.download(0x1018, 1, le32(1))) == sdo_abort::kReadOnly);
        CHECK(abort_code(m.download(0x1008, 0, bytes({'x'}))) == sdo_abort::kReadOnly);
        CHECK(abort_code(m.download(0x6041, 0, le16(1))) == sdo_abort::kReadOnly);  // TxPDO object
        CHECK(abort_code(m.download(0x1018, 0, std::vector<std::uint8_t>(18, 0), true)) == sdo_abort::kReadOnly);
    }
    SECTION("CompleteAccess not supported: 0x06010004") {
        CHECK(abort_code(m.upload(0x6040, 0, true)) == sdo_abort::kCompleteAccessUnsupported);  // a single value
        CHECK(abort_code(m.upload(0x1018, 2, true)) == sdo_abort::kCompleteAccessUnsupported);
        CHECK(abort_code(m.download(0x1C12, 2, le16(0x1600), true)) == sdo_abort::kCompleteAccessUnsupported);
    }
    SECTION("PDO configuration: count beyond the entries 0x06090030, entries while the count is set 0x06010003") {
        CHECK(abort_code(m.download(0x1600, 0, bytes({3}))) == sdo_abort::kValueOutOfRange);
        CHECK(abort_code(m.download(0x1600, 1, le32(0x60400010))) == sdo_abort::kSubindexZeroNotZero);
        REQUIRE(m.download(0x1C12, 0, bytes({0})));
        CHECK(abort_code(m.download(0x1C12, 1, le16(0x6040))) == sdo_abort::kValueOutOfRange);  // not a PDO
        REQUIRE(m.download(0x1C12, 1, le16(0x1600)));
    }
    SECTION("unknown command: 0x05040001") {
        const SdoMessage reply = m.exchange(upload_segment(false));  // no upload in progress
        CHECK(reply.command == SdoCommand::Abort);
        CHECK(reply.complete_size == sdo_abort::kUnknownCommand);

        auto raw = m.coe_message(upload_request(0x1018, 1),
                                 m.next_counter());
        raw[8] = 0xE0;  // command specifier 7
        m.write(raw);
        const auto answer = m.read();
        REQUIRE(answer);
        const auto sdo = SdoMessage::decode(ConstBytes(answer->body).subspan(2), true);
        REQUIRE(sdo);
        CHECK(sdo->command == SdoCommand::Abort);
        CHECK(sdo->index == 0x1018);
        CHECK(sdo->subindex == 1);
        CHECK(sdo->complete_size == sdo_abort::kUnknownCommand);
    }
}

TEST_CASE("a segment with the wrong toggle bit ends the transfer with 0x05030000") {
    DriveInPreop slave;
    auto& m = slave.master;
    const auto data = counting(300);

    REQUIRE(m.exchange(download_request(0x2001, 0, {data.begin(), data.begin() + 112}, 300)).command ==
            SdoCommand::Download);
    const std::vector<std::uint8_t> second_part(data.begin() + 112, data.begin() + 231);
    const SdoMessage refused = m.exchange(download_segment(true, false, second_part));  // the first carries toggle 0
    CHECK(refused.command == SdoCommand::Abort);
    CHECK(refused.index == 0x2001);
    CHECK(refused.complete_size == sdo_abort::kToggleBit);

    const SdoMessage after = m.exchange(download_segment(false, false, second_part));  // the transfer is gone
    CHECK(after.complete_size == sdo_abort::kUnknownCommand);
    CHECK(m.upload(0x2001, 0).value() == std::vector<std::uint8_t>(300, 0));  // unchanged
}

TEST_CASE("segments that do not add up to the announced size abort with 0x06070010") {
    DriveInPreop slave;
    auto& m = slave.master;
    REQUIRE(m.exchange(download_request(0x2001, 0, counting(112), 300)).command == SdoCommand::Download);
    const SdoMessage reply = m.exchange(download_segment(false, true, counting(100)));
    CHECK(reply.command == SdoCommand::Abort);
    CHECK(reply.complete_size == sdo_abort::kLengthMismatch);
}

TEST_CASE("an abort from the master ends a segmented transfer without a reply") {
    DriveInPreop slave;
    auto& m = slave.master;
    REQUIRE(m.exchange(upload_request(0x2001, 0)).complete_size == 300);
    m.write(m.coe_message(SdoMessage::abort(0x2001, 0, sdo_abort::kGeneralError), m.next_counter()));
    CHECK_FALSE(m.read());
    CHECK(m.exchange(upload_segment(false)).complete_size == sdo_abort::kUnknownCommand);
}

TEST_CASE("a request repeating the last counter is not executed again: the last reply comes again") {
    DriveInPreop slave;
    auto& m = slave.master;
    const std::uint8_t counter = m.next_counter();
    m.write(m.coe_message(download_request(0x6040, 0, le16(0x1234), 2), counter));
    const auto first = m.read();
    REQUIRE(first);

    // Same counter, another request: a retransmission of the first one.
    m.write(m.coe_message(download_request(0x6040, 0, le16(0x9999), 2), counter));
    const auto again = m.read();
    REQUIRE(again);
    CHECK(again->header == first->header);
    CHECK(again->body == first->body);
    CHECK(m.upload(0x6040, 0).value() == le16(0x1234));
}

TEST_CASE("a reply that finds SM1 full waits until the master has read it") {
    DriveInPreop slave;
    auto& m = slave.master;
    m.write(m.coe_message(upload_request(0x1018, 1), m.next_counter()));
    m.write(m.coe_message(upload_request(0x1018, 2), m.next_counter()));
    const auto first = m.read();
    REQUIRE(first);
    CHECK(SdoMessage::decode(ConstBytes(first->body).subspan(2), true)->subindex == 1);
    const auto second = m.read();
    REQUIRE(second);
    CHECK(second->header.counter == 2);
    CHECK(SdoMessage::decode(ConstBytes(second->body).subspan(2), true)->data == le32(0x00030924));
}

TEST_CASE("mailbox errors (type 0) for other protocols, bad headers and messages too short") {
    DriveInPreop slave;
    auto& m = slave.master;
    const auto error_for = [&](std::vector<std::uint8_t> message) {
        m.write(std::move(message));
        const auto reply = m.read();
        REQUIRE(reply);
        CHECK(reply->header.address == kStation);
        return mailbox_error_of(*reply);
    };
    CHECK(error_for(mailbox_message(wire::MailboxType::SoE, 10, 1, counting(10))) == 0x0002);  // a protocol it does not offer
    CHECK(error_for(mailbox_message(wire::MailboxType::Error, 4, 2, counting(4))) == 0x0005);  // invalid header
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 0, 3, {})) == 0x0005);
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 123, 4, {})) == 0x0008);  // past the 122 bytes of SM0
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 1, 5, {0})) == 0x0006);   // no room for the CoE header
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 6, 6, {0x00, 0x20, 0x40, 0x18, 0x10, 0x01})) == 0x0006);
    // CoE service 4 (TxPDO over the mailbox) is not offered.
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 10, 7, {0x00, 0x40, 1, 0, 0, 0, 0, 0, 0, 0})) == 0x0004);
    CHECK(error_for(mailbox_message(wire::MailboxType::CoE, 10, 1, {0x00, 0x00, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0})) ==
          0x0005);  // CoE service 0
}

TEST_CASE("the PDO assignment is writable in PREOP, refused in SAFEOP, and sets the SM length SAFEOP expects") {
    DriveInPreop slave;
    auto& m = slave.master;

    // 0x1600 maps 6 bytes; keep only its first entry (0x6040, 16 bits).
    REQUIRE(m.download(0x1600, 0, bytes({0})));
    REQUIRE(m.download(0x1600, 0, bytes({1})));
    slave.configure_process_data(6);
    CHECK(slave.request_state(kSafeop) == (kPreop | kError));
    CHECK(slave.status_code() == 0x001D);  // invalid output configuration
    slave.request_state(kPreop | 0x10);    // acknowledge
    slave.configure_process_data(2);
    CHECK(slave.request_state(kSafeop) == kSafeop);

    CHECK(abort_code(m.download(0x1C12, 0, bytes({0}))) == sdo_abort::kCannotStoreInState);
    CHECK(abort_code(m.download(0x1600, 0, bytes({0}))) == sdo_abort::kCannotStoreInState);
    CHECK(abort_code(m.download(0x1C13, 0, bytes({0x00, 0x00}), true)) == sdo_abort::kCannotStoreInState);
    REQUIRE(m.download(0x6040, 0, le16(6)));  // an application object stays writable
    CHECK(m.upload(0x1C12, 0).value() == bytes({1}));
    CHECK(m.upload(0x1600, 0).value() == bytes({1}));

    // Back in PREOP the whole SM2 assignment can go: then SM2 must stay disabled.
    CHECK(slave.request_state(kPreop) == kPreop);
    REQUIRE(m.download(0x1C12, 0, bytes({0})));
    slave.configure_process_data(0);
    CHECK(slave.request_state(kSafeop) == kSafeop);
}

TEST_CASE("the mailbox stopping forgets a transfer and restarts the reply counter") {
    DriveInPreop slave;
    auto& m = slave.master;
    REQUIRE(m.exchange(upload_request(0x2001, 0)).complete_size == 300);
    CHECK(slave.request_state(0x01) == 0x01);
    REQUIRE(bring_drive_to(slave.line, kStation, kPreop) == kPreop);

    m.write(m.coe_message(upload_segment(false), 1));  // the master restarts its counter too
    const auto reply = m.read();
    REQUIRE(reply);
    CHECK(reply->header.counter == 1);
    CHECK(SdoMessage::decode(ConstBytes(reply->body).subspan(2), true)->complete_size == sdo_abort::kUnknownCommand);
}

TEST_CASE("in BOOT the slave offers no CoE") {
    Slave slave(coe_drive());
    REQUIRE(slave.line.fpwr(kStation, 0x0800, bytes({0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80,
                                                     0x00, 0x22, 0x00, 0x01, 0x00})) == 1);
    REQUIRE(slave.request_state(0x03) == 0x03);
    auto& m = slave.master;
    m.write(m.coe_message(upload_request(0x1018, 1), m.next_counter()));
    const auto reply = m.read();
    REQUIRE(reply);
    CHECK(mailbox_error_of(*reply) == 0x0002);
}

TEST_CASE("a slave whose mailbox offers no CoE keeps the plain mailbox error replies") {
    EscDescription description = drive_description();
    description.mailbox->protocols = eni::kFoE;
    DriveInPreop slave(description);
    auto& m = slave.master;
    m.write(m.coe_message(upload_request(0x1018, 1), m.next_counter()));
    const auto reply = m.read();
    REQUIRE(reply);
    CHECK(mailbox_error_of(*reply) == 0x0002);
}

TEST_CASE("every CoE InitCmd of every shared ENI succeeds against its slave in PREOP, which then reaches SAFEOP") {
    int files = 0;
    int commands = 0;
    for (const auto& file : std::filesystem::directory_iterator(ECPAIR_TEST_ENI_DIR)) {
        if (file.path().extension() != ".xml") continue;
        const auto loaded = eni::load_eni_file(file.path().string());
        REQUIRE(loaded);
        ++files;
        for (const eni::Slave& eni_slave : loaded.value()->slaves) {
            if (!eni_slave.mailbox || eni_slave.mailbox->coe_init_cmds.empty()) continue;
            INFO(file.path().filename().string() << ": " << eni_slave.info.name);
            Slave slave(EscDescription::from_eni(eni_slave));
            SoemSiiReader sii(slave.line, kStation);
            const MailboxAreas areas{sii.word(0x18), sii.word(0x19), sii.word(0x1A), sii.word(0x1B)};
            MailboxMaster m(slave.line, kStation, areas);
            const auto sii_sms = sii.sync_managers();
            const auto in_bits = sii.pdo_bits(true);
            const auto out_bits = sii.pdo_bits(false);

            auto mailbox_sms = le16(areas.out_start);
            for (const auto& part : {le16(areas.out_length), bytes({0x26, 0, 1, 0}), le16(areas.in_start),
                                     le16(areas.in_length), bytes({0x22, 0, 1, 0})}) {
                mailbox_sms.insert(mailbox_sms.end(), part.begin(), part.end());
            }
            REQUIRE(slave.line.fpwr(kStation, 0x0800, mailbox_sms) == 1);
            REQUIRE(slave.request_state(kPreop) == kPreop);

            for (const eni::CoeInitCmd& cmd : eni_slave.mailbox->coe_init_cmds) {
                INFO("InitCmd line " << cmd.source_line << " " << std::hex << cmd.index << ":" << int{cmd.subindex});
                ++commands;
                // Ccs 2 with data (Advantech) is executed as a download: the master's documented choice.
                REQUIRE(!cmd.data.empty());
                CHECK(abort_code(m.download(cmd.index, cmd.subindex, cmd.data, cmd.complete_access)) == 0);
                auto read_back = m.upload(cmd.index, cmd.subindex, cmd.complete_access);
                REQUIRE(read_back);
                REQUIRE(read_back->size() >= cmd.data.size());
                auto expected = cmd.data;
                if (cmd.complete_access && cmd.subindex == 0) expected[1] = 0;  // the padding of subindex 0
                read_back->resize(expected.size());
                CHECK(*read_back == expected);
            }
            CHECK(abort_code(m.download(0x5FF0, 0, bytes({1}))) == sdo_abort::kObjectDoesNotExist);

            // The process data SyncManagers as the SII says (SOEM's ecx_config_map) pass the SAFEOP check.
            for (std::size_t s = 2; s < sii_sms.size() && s < 8; ++s) {
                std::uint16_t length = sii_sms[s].length;
                if (in_bits[s] > 0) length = static_cast<std::uint16_t>((in_bits[s] + 7) / 8);
                if (out_bits[s] > 0) length = static_cast<std::uint16_t>((out_bits[s] + 7) / 8);
                auto sm = le16(sii_sms[s].start);
                for (auto b : le16(length)) sm.push_back(b);
                for (auto b : bytes({sii_sms[s].control, 0, length > 0 ? 1 : 0, 0})) sm.push_back(b);
                REQUIRE(slave.line.fpwr(kStation, static_cast<std::uint16_t>(0x0800 + 8 * s), sm) == 1);
            }
            CHECK(slave.request_state(kSafeop) == kSafeop);
        }
    }
    CHECK(files >= 12);
    CHECK(commands > 300);
}
