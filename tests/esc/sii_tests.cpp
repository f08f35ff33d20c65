// The SII EEPROM: contents generated from the description, read back through
// the 0x0502 interface exactly as SOEM does, writes, reload, checksum, and
// every shared ENI file.

#include <algorithm>
#include <filesystem>

#include <catch2/catch.hpp>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/loader.hpp"
#include "esc_test_support.hpp"
#include "soem_sii_reader.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::uint16_t sii_status(Line& line) {
    const auto raw = line.fprd(kFirstStation, 0x0502, 2);
    return static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
}

// A write as SOEM's ecx_writeeepromFP does it: data first, then control (with
// or without the write enable bit) and address.
void write_word(Line& line, std::uint16_t word_address, std::uint16_t value, bool write_enable) {
    line.fpwr(kFirstStation, 0x0508, le16(value));
    line.fpwr(kFirstStation, 0x0502,
              {static_cast<std::uint8_t>(write_enable ? 0x01 : 0x00), 0x02, static_cast<std::uint8_t>(word_address),
               static_cast<std::uint8_t>(word_address >> 8), 0x00, 0x00});
}

std::vector<std::uint8_t> config_area(const Esc& esc) {
    return {esc.sii_image().begin(), esc.sii_image().begin() + 14};
}

}  // namespace

TEST_CASE("the test's CRC-8 reproduces a vector computed independently") {
    // Words 0C05 0000 03E8 0000 1234 0000 0000, CRC computed with Python.
    CHECK(igh_sii_crc(bytes({0x05, 0x0C, 0, 0, 0xE8, 0x03, 0, 0, 0x34, 0x12, 0, 0, 0, 0})) == 0x76);
    CHECK(igh_sii_crc(bytes({0x05, 0x0C, 0, 0, 0xE8, 0x03, 0, 0, 0, 0, 0, 0, 0, 0})) == 0x81);
}

TEST_CASE("the configuration area holds the alias in word 4 and its CRC-8 in word 7") {
    for (const std::uint16_t alias : {std::uint16_t{0}, std::uint16_t{0x1234}, std::uint16_t{1001}}) {
        auto description = drive_description();
        description.alias = alias;
        const Esc esc(description);
        const auto& image = esc.sii_image();
        CHECK(load_le<std::uint16_t>(image, 8) == alias);
        CHECK(image[14] == igh_sii_crc(config_area(esc)));
        CHECK(image[15] == 0);
        CHECK(esc.station_alias() == alias);
    }
}

TEST_CASE("SOEM's start-up reads identity, mailbox and 8-byte capability through 0x0502") {
    Line line({drive_description()});
    line.assign_station_addresses();
    SoemSiiReader sii(line, kFirstStation);
    CHECK(sii.dword(0x08) == 0x0000009A);
    CHECK(sii.eight_byte_reads());
    CHECK(sii.dword(0x0A) == 0x00030924);
    CHECK(sii.dword(0x0C) == 0x00010420);
    CHECK(sii.dword(0x0E) == 0x00C0FFEE);
    CHECK(sii.word(0x18) == 0x1000);  // standard receive mailbox (master -> slave)
    CHECK(sii.word(0x19) == 128);
    CHECK(sii.word(0x1A) == 0x1080);  // standard send mailbox
    CHECK(sii.word(0x1B) == 128);
    CHECK(sii.word(0x14) == 0x1000);  // bootstrap
    CHECK(sii.word(0x1C) == (0x04 | 0x08));  // CoE, FoE
    CHECK(sii.word(0x3F) == 1);
    // The size word says how large the EEPROM is: (KiBit - 1).
    CHECK((sii.word(0x3E) + 1U) * 128U == line[0].sii_image().size());
    CHECK(sii.read_commands() <= 8);  // 8-byte chunks are cached
}

TEST_CASE("every category parses back the way SOEM reads it") {
    Line line({drive_description("Drive 1 (ECAT_CIA402)")});
    line.assign_station_addresses();
    SoemSiiReader sii(line, kFirstStation);

    CHECK(sii.string(1) == "Drive 1 (ECAT_CIA402)");  // SOEM takes the name from string 1
    CHECK(sii.string(2) == "ecsim");
    CHECK(sii.string(3) == "0000009A:00030924");

    const std::uint32_t general = sii.find(30);
    REQUIRE(general != 0);
    CHECK(sii.byte(general + 5) == 1);     // name string index
    CHECK(sii.byte(general + 7) == 0x2F);  // CoE details: SDO, SDO Information, PDO assign/config, CompleteAccess
    CHECK(sii.byte(general + 8) == 0x01);  // FoE
    CHECK(sii.byte(general + 9) == 0x00);  // no EoE
    CHECK((sii.byte(general + 0x0D) & 0x02) == 0);  // LRW allowed
    CHECK(sii.word((general + 0x10) / 2) == 0x0011);  // ports: MII, MII

    const std::uint32_t fmmu = sii.find(40);
    REQUIRE(fmmu != 0);
    CHECK(sii.byte(fmmu + 2) == 0x01);  // outputs
    CHECK(sii.byte(fmmu + 3) == 0x02);  // inputs
    CHECK(sii.byte(fmmu + 4) == 0x03);  // mailbox state

    const auto sms = sii.sync_managers();
    REQUIRE(sms.size() == 4);
    CHECK(sms[0].start == 0x1000);
    CHECK(sms[0].length == 128);
    CHECK(sms[0].control == 0x26);
    CHECK(sms[0].type == 1);
    CHECK(sms[1].start == 0x1080);
    CHECK(sms[1].control == 0x22);
    CHECK(sms[1].type == 2);
    CHECK(sms[2].start == 0x1100);
    CHECK(sms[2].length == 6);
    CHECK(sms[2].control == 0x64);
    CHECK(sms[2].enable == 1);
    CHECK(sms[2].type == 3);
    CHECK(sms[3].start == 0x1180);
    CHECK(sms[3].length == 8);
    CHECK(sms[3].type == 4);

    const auto tx = sii.pdo_bits(true);
    const auto rx = sii.pdo_bits(false);
    CHECK(tx[3] == 64);
    CHECK(rx[2] == 48);
    CHECK(sii.find(0x1234) == 0);  // the end marker stops the search
}

TEST_CASE("a slave without mailbox has zero mailbox words and no mailbox categories") {
    Line line({io_description()});
    line.assign_station_addresses();
    SoemSiiReader sii(line, kFirstStation);
    CHECK(sii.word(0x18) == 0);
    CHECK(sii.word(0x19) == 0);
    CHECK(sii.word(0x1C) == 0);
    const auto sms = sii.sync_managers();
    REQUIRE(sms.size() == 3);
    CHECK(sms[0].type == 0);
    CHECK(sms[2].length == 1);
    CHECK(sii.pdo_bits(false)[2] == 8);
    CHECK(sii.find(50) == 0);
    const std::uint32_t general = sii.find(30);
    CHECK(sii.word((general + 0x10) / 2) == 0x0033);  // ports: EBUS, EBUS
}

TEST_CASE("an EEPROM write needs the write enable bit in the same frame") {
    Line line({drive_description()});
    line.assign_station_addresses();
    const auto last_word = static_cast<std::uint16_t>(line[0].sii_image().size() / 2 - 1);
    write_word(line, last_word, 0xBEEF, false);
    CHECK((sii_status(line) & 0x4000) != 0);  // write enable error
    CHECK(load_le<std::uint16_t>(line[0].sii_image(), 2U * last_word) == 0xFFFF);

    line.fpwr(kFirstStation, 0x0502, le16(0x0000));  // command 000 clears the errors
    CHECK((sii_status(line) & 0x7800) == 0);

    write_word(line, last_word, 0xBEEF, true);
    CHECK((sii_status(line) & 0xF801) == 0);  // no error, not busy, write enable cleared
    SoemSiiReader sii(line, kFirstStation);
    CHECK(sii.word(last_word) == 0xBEEF);
}

TEST_CASE("reload re-checks the configuration area - the alias is taken over only at power-on") {
    auto description = drive_description();
    description.alias = 0x0100;
    Line line({description});
    line.assign_station_addresses();

    write_word(line, 0x0004, 0x0200, true);  // new alias, checksum now wrong
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x04}));
    CHECK((sii_status(line) & 0x1800) == 0x1800);  // checksum error, not loaded
    CHECK(line[0].station_alias() == 0x0100);

    std::vector<std::uint8_t> area(line[0].sii_image().begin(), line[0].sii_image().begin() + 14);
    write_word(line, 0x0007, igh_sii_crc(area), true);
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x04}));
    CHECK((sii_status(line) & 0x1800) == 0);
    CHECK(line[0].station_alias() == 0x0100);  // a reload does not take the alias over

    line[0].power_off();
    line[0].power_on();
    CHECK(line[0].station_alias() == 0x0200);
}

TEST_CASE("a wrong checksum at power-on leaves the PDI dead and the process RAM inaccessible") {
    Line line({drive_description()});
    line.assign_station_addresses();
    write_word(line, 0x0004, 0x0300, true);  // checksum not fixed
    line[0].power_off();
    line[0].power_on();
    line.assign_station_addresses();
    CHECK(line[0].station_alias() == 0);
    CHECK((sii_status(line) & 0x1800) == 0x1800);
    CHECK((line.fprd(kFirstStation, 0x0110, 1)[0] & 0x01) == 0);  // PDI not operational
    CHECK(line.transact(physical_read(Command::Fprd, kFirstStation, 0x1000, 4)).wkc == 0);
    line.fpwr(kFirstStation, 0x0120, le16(0x0012));
    CHECK(line[0].al_status() == 0x01);  // nobody answers AL control
}

TEST_CASE("while the EEPROM is offered to the PDI, ECAT commands are ignored") {
    Line line({drive_description()});
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0500, bytes({0x01}));
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x01, 0x08, 0x00, 0x00, 0x00}));
    CHECK(line.fprd(kFirstStation, 0x0508, 4) == bytes({0, 0, 0, 0}));
    CHECK(line.fprd(kFirstStation, 0x0504, 2) == bytes({0, 0}));
    line.fpwr(kFirstStation, 0x0500, bytes({0x02}));  // SOEM's ecx_eeprom2master
    line.fpwr(kFirstStation, 0x0500, bytes({0x00}));
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x01, 0x08, 0x00, 0x00, 0x00}));
    CHECK(line.fprd(kFirstStation, 0x0508, 4) == bytes({0x9A, 0, 0, 0}));
}

TEST_CASE("an unknown command or an address past the EEPROM sets the command error") {
    Line line({drive_description()});
    line.assign_station_addresses();
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x03}));
    CHECK((sii_status(line) & 0x2000) != 0);
    line.fpwr(kFirstStation, 0x0502, le16(0));
    CHECK((sii_status(line) & 0x2000) == 0);
    line.fpwr(kFirstStation, 0x0502, bytes({0x00, 0x01, 0xFF, 0xFF, 0x00, 0x00}));
    CHECK((sii_status(line) & 0x2000) != 0);
}

TEST_CASE("set_eeprom_alias rewrites word 4 and the checksum - the alias shows after a power cycle") {
    Esc esc(drive_description());
    esc.set_eeprom_alias(0x4242);
    CHECK(load_le<std::uint16_t>(esc.sii_image(), 8) == 0x4242);
    CHECK(esc.sii_image()[14] == igh_sii_crc(config_area(esc)));
    CHECK(esc.station_alias() == 0);
    esc.power_off();
    esc.power_on();
    CHECK(esc.station_alias() == 0x4242);
}

TEST_CASE("every shared ENI gives ESCs whose SII reads back to the slave's identity") {
    std::size_t files = 0;
    std::size_t slaves = 0;
    for (const auto& entry : std::filesystem::directory_iterator(ECPAIR_TEST_ENI_DIR)) {
        if (entry.path().extension() != ".xml") continue;
        const auto loaded = eni::load_eni_file(entry.path().string());
        INFO(entry.path().filename().string());
        REQUIRE(loaded.has_value());
        ++files;
        std::vector<EscDescription> descriptions;
        for (const auto& slave : loaded.value()->slaves) descriptions.push_back(EscDescription::from_eni(slave));
        if (descriptions.empty()) continue;
        Line line(descriptions);
        line.assign_station_addresses();
        for (std::size_t i = 0; i < descriptions.size(); ++i) {
            const auto& slave = loaded.value()->slaves[i];
            INFO("slave " << i + 1 << " " << slave.info.name);
            SoemSiiReader sii(line, static_cast<std::uint16_t>(kFirstStation + i));
            CHECK(sii.dword(0x08) == slave.info.vendor_id);
            CHECK(sii.dword(0x0A) == slave.info.product_code);
            CHECK(sii.dword(0x0C) == slave.info.revision_no);
            CHECK(sii.dword(0x0E) == slave.info.serial_no.value_or(0));
            CHECK(sii.string(1) == slave.info.name.substr(0, 255));
            if (slave.mailbox && slave.mailbox->send && slave.mailbox->recv) {
                CHECK(sii.word(0x18) == slave.mailbox->send->start);
                CHECK(sii.word(0x19) == slave.mailbox->send->length);
                CHECK(sii.word(0x1A) == slave.mailbox->recv->start);
                CHECK(sii.word(0x1B) == slave.mailbox->recv->length);
            }
            // What SOEM would program into SM2/SM3 matches what the ENI's InitCmds write.
            const auto outputs = sii.pdo_bits(false);
            const auto inputs = sii.pdo_bits(true);
            for (const auto& sm : slave.process_data.sync_managers) {
                if (sm.type != eni::SmType::Outputs && sm.type != eni::SmType::Inputs) continue;
                const auto& bits = sm.type == eni::SmType::Outputs ? outputs : inputs;
                const auto sms = sii.sync_managers();
                REQUIRE(sm.index < sms.size());
                if (bits[sm.index] > 0) CHECK(sms[sm.index].length == (bits[sm.index] + 7) / 8);
            }
            ++slaves;
        }
    }
    CHECK(files >= 12);
    CHECK(slaves >= 35);
}

TEST_CASE("the SII advertises the SyncManagers the ENI's InitCmds write, and the slave checks against them") {
    // An older TwinCAT export writes the mailbox SMs with the ECAT event bit
    // (0x36/0x32) and has no Sm0/Sm1 elements: a real slave's ESI (and so its
    // SII) said 0x36/0x32, so the emulated one does too.
    const auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_extra/twincat_mailbox_irq_2slaves.xml"));
    REQUIRE(loaded.has_value());
    const auto& servo = loaded.value()->slaves.at(1);
    const auto description = EscDescription::from_eni(servo);
    REQUIRE(description.sm_init_writes.size() == 4);
    CHECK(description.sm_init_writes[0].control == 0x36);
    CHECK(description.sm_init_writes[1].control == 0x32);

    Line line({description});
    line.assign_station_addresses();
    SoemSiiReader sii(line, kFirstStation);
    const auto sms = sii.sync_managers();
    REQUIRE(sms.size() == 4);
    CHECK(sms[0].start == 0x1000);
    CHECK(sms[0].length == 128);
    CHECK(sms[0].control == 0x36);
    CHECK(sms[1].start == 0x1080);
    CHECK(sms[1].control == 0x32);
    CHECK(sms[2].control == 0x64);
    CHECK(sms[2].length == 6);
    CHECK(sms[3].control == 0x20);
    CHECK(sms[3].length == 6);

    const auto mailbox = [](std::uint8_t out_control, std::uint8_t in_control) {
        return bytes({0x00, 0x10, 0x80, 0x00, out_control, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80, 0x00, in_control, 0x00,
                      0x01, 0x00});
    };
    SECTION("what the InitCmds write is accepted") {
        REQUIRE(line.fpwr(kFirstStation, 0x0800, mailbox(0x36, 0x32)) == 1);
        REQUIRE(line.fpwr(kFirstStation, 0x0120, le16(0x0002)) == 1);
        CHECK(line.fprd(kFirstStation, 0x0130, 1)[0] == 0x02);
    }
    SECTION("a control byte the device does not advertise is still refused (0x0016)") {
        REQUIRE(line.fpwr(kFirstStation, 0x0800, mailbox(0x26, 0x22)) == 1);
        REQUIRE(line.fpwr(kFirstStation, 0x0120, le16(0x0002)) == 1);
        CHECK(line.fprd(kFirstStation, 0x0130, 1)[0] == 0x11);
        CHECK(load_le<std::uint16_t>(line.fprd(kFirstStation, 0x0134, 2), 0) == 0x0016);
    }
}

TEST_CASE("the bootstrap mailbox comes from the INIT -> BOOT InitCmds") {
    const auto loaded = eni::load_eni_file(std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml"));
    REQUIRE(loaded.has_value());
    const auto description = EscDescription::from_eni(loaded.value()->slaves.at(0));
    const auto bootstrap = std::count_if(description.sm_init_writes.begin(), description.sm_init_writes.end(),
                                         [](const SmInitWrite& w) { return w.bootstrap; });
    CHECK(bootstrap == 2);
    Line line({description});
    line.assign_station_addresses();
    SoemSiiReader sii(line, kFirstStation);
    CHECK(sii.word(0x14) == 0x4000);  // bootstrap receive mailbox offset
    CHECK(sii.word(0x15) == 0x0400);  // and size, as "set sm 0 (bootstrap out)" writes it
    CHECK(sii.word(0x18) == 0x4000);  // the standard mailbox, as "set sm 0 (mailbox out)" writes it
    CHECK(sii.word(0x19) == 0x0114);
}
