// Hand-made valid ENIs (tests/data/eni_extra): what no public sample has
// (Hot-Connect groups, ISO-8859-1 text, LRD/LWR-only process data) and the
// lenient spellings real exporters use.

#include "eni_test_files.hpp"

namespace ecpair::eni {
namespace {

using test::extra_eni;
using test::must_load;

TEST_CASE("Hot-Connect groups are read with their IdentifyCmds", "[eni][extra]") {
    const auto eni = must_load(extra_eni("hotconnect_groups_4slaves.xml"));
    REQUIRE(eni->slaves.size() == 4);
    CHECK_FALSE(eni->slaves[0].hot_connect);
    CHECK_FALSE(eni->slaves[2].hot_connect);

    const auto& gripper = eni->slaves[1].hot_connect.value();
    CHECK(gripper.group_name == "Gripper");
    CHECK(gripper.group_member_count == 2);
    CHECK(gripper.source_line == 56);
    REQUIRE(gripper.identify_cmds.size() == 2);
    const auto& alias = gripper.identify_cmds[0];
    CHECK(alias.transitions.empty());
    CHECK(alias.comment == "read station alias");
    CHECK(alias.command == wire::Command::Aprd);
    CHECK(alias.adp == 65535);
    CHECK(alias.ado == 0x0012);
    CHECK(alias.expected_wkc == 1);
    CHECK(alias.retries == 3);
    REQUIRE(alias.validate);
    CHECK(alias.validate->data == std::vector<std::uint8_t>{0x07, 0x00});
    CHECK(alias.validate->mask.empty());
    CHECK(gripper.identify_cmds[1].validate.value().mask == std::vector<std::uint8_t>{0xff, 0x00, 0x00, 0x00});

    const auto& tool = eni->slaves[3].hot_connect.value();
    CHECK(tool.group_name == "Tool changer");
    CHECK(tool.group_member_count == 1);
    REQUIRE(tool.identify_cmds.size() == 3);
    CHECK(tool.identify_cmds[0].command == wire::Command::Apwr);
    CHECK(tool.identify_cmds[0].ado == 0x0120);
    CHECK(tool.identify_cmds[1].ado == 0x0134);
    CHECK(tool.identify_cmds[1].requires_ == Requires::None);
    CHECK(eni->slaves[3].previous_ports.at(0).port == 'C');
}

TEST_CASE("ISO-8859-1 text becomes UTF-8", "[eni][extra]") {
    const auto eni = must_load(extra_eni("latin1_names_1slave.xml"));
    CHECK(eni->master.info.name == "Pr\xC3\xBC" "fstand S\xC3\xBC" "d");                 // Prüfstand Süd
    CHECK(eni->slaves.at(0).info.name == "Ausg\xC3\xA4nge 4\xC3\x97 24 V");           // Ausgänge 4× 24 V
    CHECK(eni->slaves.at(0).process_data.rx_pdos.at(0).name == "Kanal 1 Gr\xC3\xB6\xC3\x9F" "e");  // Größe
    CHECK(eni->cyclic.at(0).frames.at(0).cmds.at(0).comment == "Ausg\xC3\xA4nge schreiben");
    CHECK(eni->process_image->outputs->variables.at(0).name ==
          "Ausg\xC3\xA4nge 4\xC3\x97 24 V.Kanal 1 Gr\xC3\xB6\xC3\x9F" "e.Ausgang");
}

TEST_CASE("LRD/LWR-only file: no LRW, all sections read", "[eni][extra]") {
    const auto eni = must_load(extra_eni("lrd_lwr_2slaves.xml"));
    CHECK_FALSE(eni->uses_logical_read_write());
    const auto& cmds = eni->cyclic.at(0).frames.at(0).cmds;
    REQUIRE(cmds.size() == 3);
    CHECK(cmds[1].command == wire::Command::Lwr);
    CHECK(cmds[1].output_offset == 0u);
    CHECK(cmds[2].command == wire::Command::Lrd);
    CHECK(cmds[2].logical_address == 16781312);
    CHECK(cmds[0].source_line == 145);

    const auto& drive = eni->slaves.at(1);
    CHECK(drive.source_line == 46);
    CHECK(drive.process_data.send.value().bit_length == 16);
    CHECK(drive.process_data.recv.value().bit_start == 0);
    CHECK(drive.process_data.sync_managers.at(0).pdos == std::vector<std::uint16_t>{0x1600});
    CHECK(drive.process_data.sync_managers.at(0).control_byte == 100);
    CHECK(drive.mailbox.value().data_link_layer == "true");
    CHECK(drive.mailbox.value().send.value().start == 4096);
    CHECK(drive.mailbox.value().recv.value().length == 128);
    CHECK(drive.mailbox.value().poll_time_ms == 10u);
    CHECK(drive.init_cmds.at(1).transitions.contains(Transition::SI));
    CHECK(drive.init_cmds.at(1).command == wire::Command::Fpwr);
    CHECK(drive.init_cmds.at(1).adp == 1002);
    CHECK(drive.init_cmds.at(2).source_line == 116);
    CHECK(drive.previous_ports.at(0).selected);
    CHECK(drive.dc.value().shift_time_ns == 0);
    CHECK(eni->slaves.at(0).process_data.sync_managers.empty());
}

TEST_CASE("lenient spellings: hex, negative addresses, booleans, names, unknown elements", "[eni][extra]") {
    const auto eni = must_load(extra_eni("liberal_values_2slaves.xml"));
    CHECK_FALSE(eni->version);
    CHECK(eni->master.info.ether_type == 0x88A4);  // written "A488"
    CHECK_FALSE(eni->master.info.destination);

    const auto& drive = eni->slaves.at(0);
    CHECK(drive.info.name == "Drive");  // surrounding whitespace goes, even a newline inside CDATA
    CHECK(drive.info.phys_addr == 1001);  // "#x03E9"
    CHECK(drive.info.vendor_id == 0x9A);
    CHECK(drive.info.product_code == 0x00030924);  // "0x00030924"
    CHECK(drive.info.serial_no == 0xFFFFFFFFu);    // "-1"
    CHECK(drive.info.identification.value().value == 7);
    CHECK(drive.process_data.sync_managers.at(0).start_address == 0x1000);
    CHECK(drive.process_data.sync_managers.at(0).enable == true);   // "True"
    CHECK(drive.process_data.sync_managers.at(2).enable == false);  // "False"
    const auto& pdo = drive.process_data.tx_pdos.at(0);
    CHECK(pdo.fixed);
    CHECK_FALSE(pdo.mandatory);
    CHECK(pdo.sm == 3);
    CHECK(pdo.excludes == std::vector<std::uint16_t>{0x1A01});
    CHECK(pdo.entries.at(1).index == 0);  // padding
    CHECK(pdo.entries.at(1).bit_length == 8);
    const auto& coe = drive.mailbox.value().coe_init_cmds.at(0);
    CHECK(coe.ccs == 2);
    CHECK(coe.index == 0x1C12);
    CHECK(coe.subindex == 1);
    CHECK(coe.disabled);
    CHECK_FALSE(coe.complete_access);
    CHECK((drive.mailbox->protocols & kCoE) != 0);
    CHECK(drive.mailbox->status_bit_addr == 0u);
    const auto& station = drive.init_cmds.at(0);
    CHECK(station.command == wire::Command::Apwr);  // written "APWR"
    CHECK(station.transitions.contains(Transition::IP));  // written "ip"
    CHECK(station.transitions.contains(Transition::PP));
    CHECK(station.ado == 0x0010);
    CHECK(station.data == std::vector<std::uint8_t>{0xE9, 0x03});
    CHECK(drive.dc.value().shift_time_ns == -5000);

    const auto& io = eni->slaves.at(1);
    CHECK(io.info.auto_inc_addr == 0xFFFF);  // "-1"
    CHECK(io.info.ring_position == 1);
    CHECK(io.info.revision_no == 0);  // absent
    CHECK(io.init_cmds.at(0).adp == 0xFFFF);
    CHECK(io.previous_ports.at(0).port == 'B');
    CHECK(io.previous_ports.at(0).phys_addr == 1001);

    REQUIRE(eni->cyclic.size() == 1);
    CHECK_FALSE(eni->cyclic[0].cycle_time_us);
    REQUIRE(eni->cyclic[0].frames.size() == 2);
    const auto& lwr = eni->cyclic[0].frames[0].cmds.at(0);
    CHECK(lwr.command == wire::Command::Lwr);
    CHECK(lwr.logical_address == 0x01000000);
    CHECK(lwr.states.contains(SlaveState::Op));
    CHECK(lwr.states.contains(SlaveState::Safeop));
    // An LRD given as Adp/Ado: the two halves of the logical address.
    CHECK(eni->cyclic[0].frames[1].cmds.at(0).logical_address == 0x01000000);
    CHECK_FALSE(eni->process_image);
}

TEST_CASE("SoE InitCmds are read with their opcode, drive, IDN, elements and data, EoE with its header", "[eni][extra]") {
    const auto eni = must_load(extra_eni("soe_eoe_drive_2slaves.xml"));
    const auto& mailbox = eni->slaves[1].mailbox.value();
    CHECK(mailbox.protocols == (kEoE | kCoE | kFoE | kSoE));
    REQUIRE(mailbox.soe_init_cmds.size() == 6);
    const auto& telegram = mailbox.soe_init_cmds[0];
    CHECK(telegram.fixed);
    CHECK(telegram.transitions.contains(Transition::PS));
    CHECK(telegram.comment == "Telegram type");
    CHECK(telegram.opcode == 3);
    CHECK(telegram.drive_no == 0);
    CHECK(telegram.idn == 15);
    CHECK(telegram.elements == 0x40);
    CHECK(telegram.data == std::vector<std::uint8_t>{0x07, 0x00});
    CHECK(mailbox.soe_init_cmds[1].timeout == std::chrono::milliseconds(2000));
    CHECK(mailbox.soe_init_cmds[2].drive_no == 1);
    CHECK(mailbox.soe_init_cmds[2].idn == 32828);
    CHECK(mailbox.soe_init_cmds[3].data.size() == 300);
    CHECK(mailbox.soe_init_cmds[4].opcode == 1);
    CHECK(mailbox.soe_init_cmds[4].data.empty());
    CHECK(mailbox.soe_init_cmds[5].disabled);
    REQUIRE(mailbox.eoe_init_cmds.size() == 1);
    CHECK(mailbox.eoe_init_cmds[0].data.size() == 62);
}

}  // namespace
}  // namespace ecpair::eni
