// Broken ENIs (tests/data/eni_bad) each give the promised error: the right
// line, the element path of the culprit and a message naming the problem.
// Each file is tests/data/eni_extra/lrd_lwr_2slaves.xml with one thing broken
// (its comment says what). Every file in the directory must be listed here.

#include <filesystem>
#include <set>

#include "eni_test_files.hpp"

namespace ecpair::eni {
namespace {

using test::bad_eni;

struct ExpectedError {
    const char* file;
    int line;
    const char* path;
    const char* message;  // a part of the message
};


const std::vector<ExpectedError>& expected_errors() {
    static const std::vector<ExpectedError> errors = {
        {"empty.xml", 0, "", "not well-formed XML: the document has no element"},
        {"malformed_mismatched_tag.xml", 48, "", "a closing tag does not match its opening tag"},
        {"truncated.xml", 46, "", "an element is not closed"},
        {"nested_too_deep.xml", 3, "", "elements nest deeper than 100 levels"},
        {"unsupported_encoding.xml", 1, "", "the declared encoding 'UTF-16' is not supported"},
        {"wrong_root.xml", 3, "/EtherCatConfig", "the root element is <EtherCatConfig>"},
        {"missing_config.xml", 3, "/EtherCATConfig/Config", "required element is missing"},
        {"missing_master.xml", 4, "/EtherCATConfig/Config/Master", "required element is missing"},
        {"missing_slave_info.xml", 46, "/EtherCATConfig/Config/Slave[2]/Info", "required element is missing"},
        {"missing_phys_addr.xml", 47, "/EtherCATConfig/Config/Slave[2]/Info/PhysAddr", "required element is missing"},
        {"missing_vendor_id.xml", 25, "/EtherCATConfig/Config/Slave[1]/Info/VendorId", "required element is missing"},
        {"missing_product_code.xml", 47, "/EtherCATConfig/Config/Slave[2]/Info/ProductCode",
         "required element is missing"},
        {"phys_addr_out_of_range.xml", 49, "/EtherCATConfig/Config/Slave[2]/Info/PhysAddr",
         "'70000' is out of range 0..65535"},
        {"phys_addr_not_a_number.xml", 49, "/EtherCATConfig/Config/Slave[2]/Info/PhysAddr", "'10O2' is not a number"},
        {"phys_addr_negative.xml", 49, "/EtherCATConfig/Config/Slave[2]/Info/PhysAddr", "'-2' is out of range 0..65535"},
        {"cmd_out_of_range.xml", 111, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]/Cmd",
         "'300' is out of range 0..255"},
        {"unknown_command_code.xml", 17, "/EtherCATConfig/Config/Master/InitCmds/InitCmd[1]/Cmd",
         "command code '20' is not an EtherCAT datagram type"},
        {"data_length_too_large.xml", 169, "/EtherCATConfig/Config/Cyclic[1]/Frame[1]/Cmd[3]/DataLength",
         "'1487' is out of range 0..1486"},
        {"hex_odd_digits.xml", 42, "/EtherCATConfig/Config/Slave[1]/InitCmds/InitCmd[1]/Data",
         "'e90' is not hexBinary (odd number of hex digits)"},
        {"hex_not_hex.xml", 126, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[3]/Validate/Data",
         "'02zz' is not hexBinary"},
        {"unknown_transition.xml", 109, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]/Transition[2]",
         "unknown transition code 'SX'"},
        {"unknown_state.xml", 148, "/EtherCATConfig/Config/Cyclic[1]/Frame[1]/Cmd[1]/State[3]", "unknown state 'RUN'"},
        {"cyclic_cmd_missing_cmd.xml", 155, "/EtherCATConfig/Config/Cyclic[1]/Frame[1]/Cmd[2]/Cmd",
         "required element is missing"},
        {"cyclic_cmd_missing_state.xml", 164, "/EtherCATConfig/Config/Cyclic[1]/Frame[1]/Cmd[3]/State",
         "required element is missing"},
        {"bad_boolean.xml", 15, "/EtherCATConfig/Config/Master/InitCmds/InitCmd[1]/BeforeSlave",
         "'yes' is not a boolean"},
        {"duplicate_phys_addr.xml", 49, "/EtherCATConfig/Config/Slave[2]/Info/PhysAddr",
         "PhysAddr 1001 is already used by Slave[1]"},
        {"duplicate_ring_position.xml", 50, "/EtherCATConfig/Config/Slave[2]/Info/AutoIncAddr",
         "ring position 0 (AutoIncAddr 0) is already taken by Slave[1]"},
        {"previous_port_unknown.xml", 134, "/EtherCATConfig/Config/Slave[2]/PreviousPort[1]/PhysAddr",
         "no slave in this file has PhysAddr 1005"},
        {"bad_port.xml", 133, "/EtherCATConfig/Config/Slave[2]/PreviousPort[1]/Port", "'E' is not a port"},
        {"validate_mask_length.xml", 127, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[3]/Validate/DataMask",
         "DataMask has 1 byte(s) but Data has 2"},
        {"data_length_mismatch.xml", 43, "/EtherCATConfig/Config/Slave[1]/InitCmds/InitCmd[1]/DataLength",
         "DataLength 4 does not match the 2 bytes of <Data>"},
        {"bad_mac.xml", 9, "/EtherCATConfig/Config/Master/Info/Source", "'0200000001' is not a MAC address"},
        {"physical_cmd_without_ado.xml", 13, "/EtherCATConfig/Config/Master/InitCmds/InitCmd[1]/Ado",
         "required element is missing"},
        {"logical_cmd_without_addr.xml", 164, "/EtherCATConfig/Config/Cyclic[1]/Frame[1]/Cmd[3]/Addr",
         "required element is missing"},
        {"unknown_sm_type.xml", 66, "/EtherCATConfig/Config/Slave[2]/ProcessData/Sm2/Type",
         "unknown SyncManager type 'Output'"},
        {"bad_ccs.xml", 90, "/EtherCATConfig/Config/Slave[2]/Mailbox/CoE/InitCmds/InitCmd[1]/Ccs",
         "'3' is not 1 (download) or 2 (upload)"},
        {"aoe_init_cmds.xml", 98, "/EtherCATConfig/Config/Slave[2]/Mailbox/AoE/InitCmds",
         "AoE InitCmds are not supported: ecpair runs the CoE, EoE and SoE InitCmds"},
        {"soe_bad_opcode.xml", 101, "/EtherCATConfig/Config/Slave[2]/Mailbox/SoE/InitCmds/InitCmd[1]/OpCode",
         "'2' is not 3 (write) or 1 (read)"},
        {"coe_index_out_of_range.xml", 91, "/EtherCATConfig/Config/Slave[2]/Mailbox/CoE/InitCmds/InitCmd[1]/Index",
         "'70000' is out of range 0..65535"},
        {"bad_complete_access.xml", 86,
         "/EtherCATConfig/Config/Slave[2]/Mailbox/CoE/InitCmds/InitCmd[1]/@CompleteAccess",
         "'maybe' is not a boolean"},
        {"unknown_requires.xml", 111, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]/Requires",
         "unknown Requires value 'always'"},
        {"variable_missing_name.xml", 187, "/EtherCATConfig/Config/ProcessImage/Outputs/Variable[1]/Name",
         "required element is missing"},
        {"hot_connect_no_members.xml", 138, "/EtherCATConfig/Config/Slave[2]/HotConnect/GroupMemberCnt",
         "a Hot-Connect group has at least one member"},
        {"fmmu_record_impossible.xml", 107, "/EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]",
         "FMMU 0 record (00000001020000070011000701000000) cannot be right: type 0x07"},
        {"encrypted_scrambled_2slaves.xml", 87, "/EncryptedEtherCATConfig/Config/Slave[1]/InitCmds/InitCmd[1]",
         "this ENI is encrypted (<EncryptedEtherCATConfig EncryptionVersion=\"1\">): the data of its InitCmds does not "
         "decode (it writes AL control 0xad55, which requests no state"},
    };
    return errors;
}

TEST_CASE("every broken ENI gives its promised error", "[eni][bad]") {
    for (const auto& expected : expected_errors()) {
        SECTION(expected.file) {
            const auto result = load_eni_file(bad_eni(expected.file));
            REQUIRE_FALSE(result.has_value());
            const auto& error = result.error();
            INFO(error.describe());
            CHECK(error.file == bad_eni(expected.file));
            CHECK(error.line == expected.line);
            CHECK(error.element_path == expected.path);
            CHECK_THAT(error.message, Catch::Contains(expected.message));
        }
    }
}

TEST_CASE("every file in eni_bad has an expected error", "[eni][bad]") {
    std::set<std::string> listed;
    for (const auto& expected : expected_errors()) listed.insert(expected.file);
    for (const auto& entry : std::filesystem::directory_iterator(std::string(ECPAIR_TEST_DATA_DIR "/eni_bad"))) {
        INFO(entry.path().filename().string());
        CHECK(listed.count(entry.path().filename().string()) == 1);
    }
}

TEST_CASE("an encrypted ENI is refused with what to do about it", "[eni][bad]") {
    const auto result = load_eni_file(bad_eni("encrypted_scrambled_2slaves.xml"));
    REQUIRE_FALSE(result.has_value());
    INFO(result.error().describe());
    CHECK_THAT(result.error().message, Catch::Contains("ecpair reads plain ENIs only") &&
                                           Catch::Contains("export the configuration again without encryption"));
}

TEST_CASE("describe() puts file, line, path and message together", "[eni][bad]") {
    const auto result = load_eni_file(bad_eni("phys_addr_out_of_range.xml"));
    REQUIRE_FALSE(result.has_value());
    CHECK(result.error().describe() ==
          bad_eni("phys_addr_out_of_range.xml") +
              ":49: /EtherCATConfig/Config/Slave[2]/Info/PhysAddr: '70000' is out of range 0..65535");
}

TEST_CASE("file problems: missing, a directory", "[eni][bad]") {
    const auto missing = load_eni_file(bad_eni("no_such_file.xml"));
    REQUIRE_FALSE(missing.has_value());
    CHECK(missing.error().line == 0);
    CHECK(missing.error().element_path.empty());
    CHECK_THAT(missing.error().message, Catch::Contains("cannot open the file"));
    CHECK(missing.error().describe() == bad_eni("no_such_file.xml") + ": " + missing.error().message);

    const auto directory = load_eni_file(std::string(ECPAIR_TEST_DATA_DIR "/eni_bad"));
    REQUIRE_FALSE(directory.has_value());
    CHECK_THAT(directory.error().message, Catch::Contains("not a regular file"));
}

TEST_CASE("errors from strings carry the given name", "[eni][bad]") {
    const auto result = load_eni_string("<EtherCATConfig>\n<Config/>\n</EtherCATConfig>", "inline.xml");
    REQUIRE_FALSE(result.has_value());
    CHECK(result.error().describe() == "inline.xml:2: /EtherCATConfig/Config/Master: required element is missing");
}

}  // namespace
}  // namespace ecpair::eni
