// Register InitCmds whose data cannot be right are refused at their
// InitCmd: FMMU records with bits out of range, reserved type bits, an
// activate byte that is neither 0 nor 1, an active record mapping nothing or
// past 4 GiB; a station address other than the slave's PhysAddr; an AL
// control write that requests no state. Under <EncryptedEtherCATConfig> a
// station address or AL control that does not decode means an encrypted body
// and the file is refused as encrypted; FMMU records alone that do not decode
// (the Murrelektronik export) and a plain body under that root load.

#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "eni_test_files.hpp"

namespace ecpair::eni {
namespace {

using test::extra_eni;
using test::must_load;

// lrd_lwr_2slaves.xml with one more InitCmd for the Drive (station 1002): `cmd`, `ado`, `data`.
std::string with_drive_init_cmd(int cmd, std::uint16_t ado, const std::string& data, bool encrypted_root = false) {
    std::ifstream in(extra_eni("lrd_lwr_2slaves.xml"));
    std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string anchor = "          <Data>ea03</Data>\n        </InitCmd>\n";
    const auto at = xml.find(anchor);
    REQUIRE(at != std::string::npos);
    xml.insert(at + anchor.size(), fmt::format("        <InitCmd>\n          <Transition>PS</Transition>\n"
                                               "          <Cmd>{}</Cmd>\n          <Adp>1002</Adp>\n"
                                               "          <Ado>{}</Ado>\n          <Data>{}</Data>\n        </InitCmd>\n",
                                               cmd, ado, data));
    if (encrypted_root) {
        const auto replace = [&xml](const std::string& from, const std::string& to) {
            const auto pos = xml.find(from);
            REQUIRE(pos != std::string::npos);
            xml.replace(pos, from.size(), to);
        };
        replace("<EtherCATConfig Version=\"1.3\">", "<EncryptedEtherCATConfig Version=\"1.3\" EncryptionVersion=\"1\">");
        replace("</EtherCATConfig>", "</EncryptedEtherCATConfig>");
    }
    return xml;
}

// One FMMU record: logical 0x01000000, 2 bytes, bits 0..7, physical 0x1100, `type`, `activate`.
std::string fmmu(std::string logical = "00000001", std::string length = "0200", std::string start_bit = "00",
                 std::string stop_bit = "07", std::string physical_bit = "00", std::string type = "02",
                 std::string activate = "01") {
    return logical + length + start_bit + stop_bit + "0011" + physical_bit + type + activate + "000000";
}

std::string error_of(const std::string& xml) {
    const auto result = load_eni_string(xml, "test.xml");
    REQUIRE_FALSE(result.has_value());
    INFO(result.error().describe());
    CHECK(result.error().element_path == "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]");
    return result.error().message;
}

}  // namespace

TEST_CASE("FMMU records that cannot be right are refused at their InitCmd", "[eni][registers]") {
    struct Case {
        std::string record;
        const char* why;
    };
    const std::vector<Case> cases = {
        {fmmu("00000001", "0200", "08"), "logical start bit 8 (a bit is 0..7)"},
        {fmmu("00000001", "0200", "00", "09"), "logical stop bit 9 (a bit is 0..7)"},
        {fmmu("00000001", "0200", "00", "07", "0a"), "physical start bit 10 (a bit is 0..7)"},
        {fmmu("00000001", "0200", "00", "07", "00", "04"), "type 0x04"},
        {fmmu("00000001", "0200", "00", "07", "00", "02", "5a"), "activate 0x5a (0 or 1)"},
        {fmmu("00000001", "0000"), "it is active but maps 0 bytes"},
        {fmmu("00000001", "0200", "00", "07", "00", "00"), "it is active but neither reads nor writes (type 0)"},
        {fmmu("ffffffff", "0200"), "runs past the 4 GiB address space"},
        {fmmu("00000001", "0100", "05", "02"), "the stop bit lies before the start bit"},
    };
    for (const auto& c : cases) {
        INFO(c.record);
        CHECK_THAT(error_of(with_drive_init_cmd(5, 0x0600, c.record)), Catch::Contains("FMMU 0 record") && Catch::Contains(c.why));
    }
    // The second record of a two-record write is named by its number.
    CHECK_THAT(error_of(with_drive_init_cmd(5, 0x0600, fmmu() + fmmu("00000001", "0200", "00", "07", "00", "07"))),
               Catch::Contains("FMMU 1 record"));
    // Inactive records, partial writes and a good record load.
    CHECK(load_eni_string(with_drive_init_cmd(5, 0x0600, fmmu()), "test.xml"));
    CHECK(load_eni_string(with_drive_init_cmd(5, 0x0600, std::string(64, '0')), "test.xml"));
    CHECK(load_eni_string(with_drive_init_cmd(5, 0x060C, "01"), "test.xml"));
}

TEST_CASE("a station address other than the PhysAddr, and an AL control without a state, are refused", "[eni][registers]") {
    CHECK_THAT(error_of(with_drive_init_cmd(2, 0x0010, "eb03")),
               Catch::Contains("it sets station address 1003 but the slave's PhysAddr is 1002"));
    CHECK_THAT(error_of(with_drive_init_cmd(5, 0x0120, "0700")), Catch::Contains("it writes AL control 0x0700, which requests no state"));
    CHECK_THAT(error_of(with_drive_init_cmd(5, 0x0120, "0201")), Catch::Contains("requests no state"));
    // Error acknowledge and the ID request go with a state.
    CHECK(load_eni_string(with_drive_init_cmd(5, 0x0120, "1200"), "test.xml"));
    CHECK(load_eni_string(with_drive_init_cmd(5, 0x0120, "2100"), "test.xml"));
}

TEST_CASE("under EncryptedEtherCATConfig, data that does not decode means an encrypted file", "[eni][registers]") {
    const auto result = load_eni_string(with_drive_init_cmd(2, 0x0010, "3f9a", true), "test.xml");
    REQUIRE_FALSE(result.has_value());
    INFO(result.error().describe());
    CHECK_THAT(result.error().message, Catch::StartsWith("this ENI is encrypted (<EncryptedEtherCATConfig EncryptionVersion=\"1\">)") &&
                                           Catch::Contains("station address 39487"));
    const auto al_control = load_eni_string(with_drive_init_cmd(5, 0x0120, "c7e1", true), "test.xml");
    REQUIRE_FALSE(al_control.has_value());
    CHECK_THAT(al_control.error().message, Catch::StartsWith("this ENI is encrypted") &&
                                               Catch::Contains("export the configuration again without encryption"));
    // A plain body under the same root loads.
    const auto plain = load_eni_string(with_drive_init_cmd(5, 0x0600, fmmu(), true), "test.xml");
    INFO((plain ? std::string() : plain.error().describe()));
    REQUIRE(plain);
    CHECK((*plain)->root_element == "EncryptedEtherCATConfig");
    // So does one whose FMMU records alone do not decode, as the Murrelektronik export's (its LRW split is
    // refused where the plan is made); the same record under <EtherCATConfig> is refused.
    const auto scrambled_fmmu = fmmu("00000001", "0200", "00", "fc", "00", "f9");
    const auto fmmu_only = load_eni_string(with_drive_init_cmd(5, 0x0600, scrambled_fmmu, true), "test.xml");
    INFO((fmmu_only ? std::string() : fmmu_only.error().describe()));
    CHECK(fmmu_only);
    CHECK_THAT(error_of(with_drive_init_cmd(5, 0x0600, scrambled_fmmu)), Catch::Contains("logical stop bit 252"));
}

}  // namespace ecpair::eni
