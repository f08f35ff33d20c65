// Every real ENI in tests/data/eni loads, with the right counts and values.
//
// The expected counts were taken independently of the loader, with Python's
// xml.etree on each file:
//   slaves        len(Config.findall('Slave'))
//   master        len(Config.findall('Master/InitCmds/InitCmd'))
//   esc           len(Config.findall('Slave/InitCmds/InitCmd'))
//   coe           len(Config.findall('Slave/Mailbox/CoE/InitCmds/InitCmd'))
//   cyclic        len(Config.findall('Cyclic/Frame/Cmd'))
//   in/out vars   len(Config.findall('ProcessImage/Inputs|Outputs/Variable'))
// and they agree with SOURCES.md where it names a number (7 slaves: 133 CoE,
// 355 = 12 + 343 register InitCmds). Spot values were read off the files.

#include <algorithm>
#include <numeric>

#include "eni_test_files.hpp"

namespace ecpair::eni {
namespace {

using test::must_load;
using test::real_eni;

struct ExpectedCounts {
    const char* file;
    std::size_t slaves, master_init_cmds, slave_init_cmds, coe_init_cmds, cyclic_cmds, input_vars, output_vars;
};

constexpr ExpectedCounts kCounts[] = {
    {"advantech_amax4270_1slave.xml", 1, 0, 0, 33, 0, 0, 0},
    {"advantech_empty_ring_0slaves.xml", 0, 0, 0, 0, 0, 0, 0},
    {"advantech_io_ring_4slaves.xml", 4, 0, 0, 0, 0, 0, 0},
    {"ecengineer_murrelektronik_encrypted_2slaves.xml", 2, 12, 65, 103, 3, 171, 163},
    {"ecengineer_rocos_elmo_1slave.xml", 1, 12, 49, 20, 5, 5, 5},
    {"ecengineer_rocos_elmo_3slaves_bcr.xml", 3, 12, 147, 60, 5, 15, 15},
    {"ecengineer_rocos_elmo_4slaves.xml", 4, 12, 196, 80, 5, 20, 20},
    {"ecengineer_rocos_elmo_7slaves.xml", 7, 12, 343, 133, 5, 56, 35},
    {"ecengineer_rocos_rdm_6slaves.xml", 6, 12, 288, 90, 5, 30, 24},
    {"elmo_eas_rocos_1slave.xml", 1, 7, 44, 4, 2, 5, 7},
    {"twincat_cherryecat_cia402_1slave.xml", 1, 12, 39, 3, 3, 21, 5},
    {"twincat_kpierczy_5slaves.xml", 5, 12, 237, 48, 6, 34, 11},
};

std::size_t slave_init_cmds(const EniConfig& eni) {
    return std::accumulate(eni.slaves.begin(), eni.slaves.end(), std::size_t{0},
                           [](std::size_t n, const Slave& s) { return n + s.init_cmds.size(); });
}

std::size_t coe_init_cmds(const EniConfig& eni) {
    return std::accumulate(eni.slaves.begin(), eni.slaves.end(), std::size_t{0}, [](std::size_t n, const Slave& s) {
        return n + (s.mailbox ? s.mailbox->coe_init_cmds.size() : 0);
    });
}

std::size_t cyclic_cmds(const EniConfig& eni) {
    std::size_t n = 0;
    for (const auto& cyclic : eni.cyclic) {
        for (const auto& frame : cyclic.frames) n += frame.cmds.size();
    }
    return n;
}

std::size_t variables(const std::optional<ProcessImage>& image, bool inputs) {
    if (!image) return 0;
    const auto& section = inputs ? image->inputs : image->outputs;
    return section ? section->variables.size() : 0;
}

const CyclicCmd& cyclic_cmd(const EniConfig& eni, std::size_t index) {
    return eni.cyclic.at(0).frames.at(0).cmds.at(index);
}

TEST_CASE("every real ENI loads with the counts counted independently", "[eni][real]") {
    for (const auto& expected : kCounts) {
        SECTION(expected.file) {
            const auto eni = must_load(real_eni(expected.file));
            CHECK(eni->slaves.size() == expected.slaves);
            CHECK(eni->master.init_cmds.size() == expected.master_init_cmds);
            CHECK(slave_init_cmds(*eni) == expected.slave_init_cmds);
            CHECK(coe_init_cmds(*eni) == expected.coe_init_cmds);
            CHECK(cyclic_cmds(*eni) == expected.cyclic_cmds);
            CHECK(variables(eni->process_image, true) == expected.input_vars);
            CHECK(variables(eni->process_image, false) == expected.output_vars);
            CHECK(eni->source_path == real_eni(expected.file));
        }
    }
}

TEST_CASE("TwinCAT file: validate mask, CompleteAccess, Identification 0x134", "[eni][real]") {
    const auto eni = must_load(real_eni("twincat_cherryecat_cia402_1slave.xml"));
    CHECK(eni->root_element == "EtherCATConfig");
    CHECK(eni->version == "1.3");
    CHECK(eni->master.info.name == "Device 2 (EtherCAT)");
    REQUIRE(eni->master.info.destination);
    CHECK(eni->master.info.destination->to_string() == "01:01:05:01:00:00");
    CHECK(eni->master.info.ether_type == 0x88A4);
    REQUIRE(eni->master.mailbox_states);
    CHECK(eni->master.mailbox_states->start_addr == 0x09000000);
    CHECK(eni->master.mailbox_states->count == 1);

    const auto& slave = eni->slaves.at(0);
    REQUIRE(slave.info.identification);
    CHECK(slave.info.identification->ado == 0x0134);
    CHECK(slave.info.identification->value == 0);
    CHECK(slave.info.identification->enabled);

    // InitCmd 2: "check device state for INIT", APRD 0x130, Validate 0100 / 0f00 / 5000 ms.
    const auto& check = slave.init_cmds.at(1);
    CHECK(check.comment == "check device state for INIT");
    CHECK(check.ado == 0x0130);
    REQUIRE(check.validate);
    CHECK(check.validate->data == std::vector<std::uint8_t>{0x01, 0x00});
    CHECK(check.validate->mask == std::vector<std::uint8_t>{0x0f, 0x00});
    CHECK(check.validate->timeout == std::chrono::milliseconds(5000));

    // CoE 1: CompleteAccess download of 0x1C12:0 with "01000216" (1 entry, 0x1602).
    const auto& coe = slave.mailbox.value().coe_init_cmds;
    CHECK(coe.at(0).complete_access);
    CHECK(coe.at(0).fixed);
    CHECK(coe.at(0).index == 0x1C12);
    CHECK(coe.at(0).subindex == 0);
    CHECK(coe.at(0).ccs == 1);
    CHECK(coe.at(0).transitions.contains(Transition::PS));
    CHECK(coe.at(0).data == std::vector<std::uint8_t>{0x01, 0x00, 0x02, 0x16});
    CHECK_FALSE(coe.at(2).complete_access);
    CHECK(coe.at(2).transitions.contains(Transition::SO));
    CHECK(coe.at(2).index == 0x6060);

    CHECK(eni->cyclic.at(0).cycle_time_us == 2000u);
    REQUIRE(eni->process_image);
    CHECK(eni->process_image->inputs->byte_size == 1536);
}

TEST_CASE("TwinCAT 5-slave file: ring positions, ARMW on the second slave, IMU serial", "[eni][real]") {
    const auto eni = must_load(real_eni("twincat_kpierczy_5slaves.xml"));
    const std::vector<std::uint16_t> auto_inc{0, 65535, 65534, 65533, 65532};
    for (std::size_t i = 0; i < eni->slaves.size(); ++i) {
        CHECK(eni->slaves[i].info.auto_inc_addr == auto_inc[i]);
        CHECK(eni->slaves[i].info.ring_position == i);
        CHECK(eni->slaves[i].info.phys_addr == 1001 + i);
    }
    CHECK(eni->slaves[0].info.name == "Imu");
    CHECK(eni->slaves[0].info.serial_no == 1u);
    CHECK(eni->slaves[0].info.vendor_id != 0);
    // The IMU's Sm2 is disabled ("0"), its Sm3 enabled ("1").
    const auto& sms = eni->slaves[0].process_data.sync_managers;
    REQUIRE(sms.size() == 2);
    CHECK(sms[0].index == 2);
    CHECK(sms[0].enable == false);
    CHECK(sms[1].enable == true);
    CHECK(eni->slaves[1].dc.value().reference_clock);
    CHECK_FALSE(eni->slaves[2].dc.value().reference_clock);

    const auto& armw = cyclic_cmd(*eni, 1);
    CHECK(armw.command == wire::Command::Armw);
    CHECK(armw.adp == 65535);
    CHECK(armw.ado == 0x0910);
    CHECK_FALSE(armw.expected_wkc);
    const auto& lrd = cyclic_cmd(*eni, 3);
    CHECK(lrd.command == wire::Command::Lrd);
    CHECK(lrd.logical_address == 0x01000000);
    CHECK(lrd.data_length == 14);
    CHECK(lrd.expected_wkc == 1);
    CHECK(lrd.input_offset == 61u);
    CHECK(lrd.states.contains(SlaveState::Safeop));
    CHECK(lrd.states.contains(SlaveState::Op));
    CHECK_FALSE(lrd.states.contains(SlaveState::Preop));
    CHECK(cyclic_cmd(*eni, 4).command == wire::Command::Lrw);
    CHECK(cyclic_cmd(*eni, 4).expected_wkc == 12);
    CHECK(eni->uses_logical_read_write());
    CHECK(eni->cyclic.at(0).cycle_time_us == 10000u);
}

TEST_CASE("EC-Engineer RDM file: name with a newline, PP transition, ring order", "[eni][real]") {
    const auto eni = must_load(real_eni("ecengineer_rocos_rdm_6slaves.xml"));
    CHECK(eni->slaves.at(0).info.name == "Slave_1001 [RDM\n]");
    CHECK(eni->slaves.at(5).info.name == "Slave_1006 [RDM\n]");
    CHECK(eni->slaves.at(5).info.auto_inc_addr == 65531);
    CHECK(eni->slaves.at(5).info.ring_position == 5);
    CHECK(eni->slaves.at(0).info.vendor_id == 171);

    // Slave 1, InitCmd 25: "clear DC activation", FPWR 1001:0x980 in IP and PP.
    const auto& clear_dc = eni->slaves.at(0).init_cmds.at(24);
    CHECK(clear_dc.comment == "clear DC activation");
    CHECK(clear_dc.transitions.contains(Transition::PP));
    CHECK(clear_dc.transitions.contains(Transition::IP));
    CHECK_FALSE(clear_dc.transitions.contains(Transition::PS));
    CHECK(clear_dc.command == wire::Command::Fpwr);
    CHECK(clear_dc.adp == 1001);
    CHECK(clear_dc.ado == 0x0980);
    CHECK(clear_dc.data == std::vector<std::uint8_t>{0x00, 0x00});
}

TEST_CASE("EC-Engineer 1-slave file: master broadcasts, DC, LRW", "[eni][real]") {
    const auto eni = must_load(real_eni("ecengineer_rocos_elmo_1slave.xml"));
    CHECK(eni->master.info.name == "Class-A Master");
    CHECK(eni->master.info.destination == wire::MacAddress::broadcast());
    REQUIRE(eni->master.eoe);
    const auto& first = eni->master.init_cmds.at(0);
    CHECK(first.before_slave);
    CHECK(first.command == wire::Command::Brd);
    CHECK(first.ado == 0x0130);
    CHECK(first.requires_ == Requires::Cycle);
    const auto& slave = eni->slaves.at(0);
    REQUIRE(slave.dc);
    CHECK(slave.dc->reference_clock);
    CHECK(slave.dc->cycle_time0_ns == 1000000u);
    REQUIRE(slave.mailbox);
    CHECK(slave.mailbox->bootstrap_send);
    CHECK(slave.mailbox->bootstrap_recv);
    const auto& lrw = cyclic_cmd(*eni, 4);
    CHECK(lrw.command == wire::Command::Lrw);
    CHECK(lrw.logical_address == 0x10000000);
    CHECK(lrw.expected_wkc == 3);
    CHECK(eni->uses_logical_read_write());
}

TEST_CASE("EC-Engineer 4-slave file: LRW Cnt 12 and a PreviousPort chain on port B", "[eni][real]") {
    const auto eni = must_load(real_eni("ecengineer_rocos_elmo_4slaves.xml"));
    CHECK(cyclic_cmd(*eni, 4).expected_wkc == 12);
    CHECK(eni->slaves.at(0).previous_ports.empty());
    for (std::size_t i = 1; i < eni->slaves.size(); ++i) {
        REQUIRE(eni->slaves[i].previous_ports.size() == 1);
        CHECK(eni->slaves[i].previous_ports[0].port == 'B');
        CHECK(eni->slaves[i].previous_ports[0].phys_addr == eni->slaves[i - 1].info.phys_addr);
    }
}

TEST_CASE("Murrelektronik file: EncryptedEtherCATConfig root with plain content", "[eni][real]") {
    const auto eni = must_load(real_eni("ecengineer_murrelektronik_encrypted_2slaves.xml"));
    CHECK(eni->root_element == "EncryptedEtherCATConfig");
    CHECK(eni->version == "1.3");
    CHECK(eni->master.info.source->to_string() == "00:13:95:52:11:b4");
    CHECK(eni->master.eoe->max_ports == 2);
    CHECK(eni->master.eoe->max_frames == 120);
    CHECK(eni->master.eoe->max_macs == 100);
    CHECK_FALSE(eni->slaves.at(0).mailbox);  // the EBC coupler has none
    const auto& mailbox = eni->slaves.at(1).mailbox.value();
    CHECK(mailbox.protocols == (kAoE | kEoE | kCoE | kFoE));
    CHECK(mailbox.aoe_net_id == "1.1.1.1.3.234");
    CHECK(mailbox.status_bit_addr == 0u);
    CHECK(mailbox.eoe_init_cmds.size() == 1);
}

TEST_CASE("EAS file: Identification 0x12, Requires frame, EoE Disabled, LRD + LWR", "[eni][real]") {
    const auto eni = must_load(real_eni("elmo_eas_rocos_1slave.xml"));
    CHECK_FALSE(eni->version);  // EAS writes <EtherCATConfig> bare
    CHECK(eni->master.info.name == "Master 1");
    const auto& slave = eni->slaves.at(0);
    REQUIRE(slave.info.identification);
    CHECK(slave.info.identification->ado == 0x0012);
    CHECK(slave.info.identification->value == 0);
    CHECK_FALSE(slave.info.identification->enabled);  // EnableIdentification="False"
    CHECK(slave.info.physics == "YY");
    CHECK(slave.init_cmds.at(18).comment == "clear sm 0 (mailbox out)");
    CHECK(slave.init_cmds.at(18).requires_ == Requires::Frame);
    const auto& mailbox = slave.mailbox.value();
    CHECK(mailbox.poll_time_ms == 3000u);
    CHECK(mailbox.protocols == (kEoE | kFoE | kCoE));
    REQUIRE(mailbox.eoe_init_cmds.size() == 1);
    CHECK_FALSE(mailbox.eoe_init_cmds[0].disabled);
    CHECK(mailbox.eoe_init_cmds[0].data.size() == 58);
    CHECK(mailbox.eoe_init_cmds[0].comment == "EoE init command, ip settings");
    CHECK(mailbox.coe_init_cmds.at(0).complete_access);
    CHECK(mailbox.coe_init_cmds.at(2).index == 0x6060);

    const auto& lrd = cyclic_cmd(*eni, 0);
    CHECK(lrd.command == wire::Command::Lrd);
    CHECK(lrd.logical_address == 69632);
    CHECK(lrd.input_offset == 0u);
    CHECK_FALSE(lrd.output_offset);
    const auto& lwr = cyclic_cmd(*eni, 1);
    CHECK(lwr.command == wire::Command::Lwr);
    CHECK(lwr.data_length == 16);
    CHECK(lwr.output_offset == 0u);
    CHECK_FALSE(lwr.input_offset);
    CHECK_FALSE(eni->uses_logical_read_write());
    CHECK_FALSE(eni->cyclic.at(0).cycle_time_us);
}

TEST_CASE("Advantech files: positive AutoIncAddr, MBox SM types, Ccs 2 with data, #x01 SubIndex", "[eni][real]") {
    const auto ring = must_load(real_eni("advantech_io_ring_4slaves.xml"));
    CHECK_FALSE(ring->version);
    CHECK_FALSE(ring->process_image);
    CHECK(ring->cyclic.at(0).frames.empty());
    const std::vector<std::uint16_t> phys{1, 4, 33, 85};
    for (std::size_t i = 0; i < ring->slaves.size(); ++i) {
        CHECK(ring->slaves[i].info.auto_inc_addr == i);
        CHECK(ring->slaves[i].info.ring_position == i);
        CHECK(ring->slaves[i].info.phys_addr == phys[i]);
    }
    const auto& coupler = ring->slaves[0];
    REQUIRE(coupler.process_data.sync_managers.size() == 4);
    CHECK(coupler.process_data.sync_managers[0].type == SmType::MailboxOut);
    CHECK(coupler.process_data.sync_managers[1].type == SmType::MailboxIn);
    CHECK(coupler.process_data.sync_managers[2].type == SmType::Outputs);
    CHECK(coupler.process_data.sync_managers[3].type == SmType::Inputs);
    // No <Protocol> elements, but a <CoE> element: CoE is supported.
    CHECK((coupler.mailbox.value().protocols & kCoE) != 0);

    const auto amax = must_load(real_eni("advantech_amax4270_1slave.xml"));
    const auto& coe = amax->slaves.at(0).mailbox.value().coe_init_cmds;
    CHECK(std::all_of(coe.begin(), coe.end(), [](const CoeInitCmd& c) { return c.ccs == 2; }));
    CHECK(coe.at(2).index == 0x1C12);
    CHECK(coe.at(2).subindex == 1);  // written "#x01"
    CHECK(coe.at(2).data == std::vector<std::uint8_t>{0x00, 0x16});
    CHECK(coe.at(2).timeout == std::chrono::milliseconds(100));

    const auto empty = must_load(real_eni("advantech_empty_ring_0slaves.xml"));
    CHECK(empty->slaves.empty());
    CHECK(empty->cyclic.at(0).cycle_time_us == 1000u);
    CHECK(empty->master.info.ether_type == 0x88A4);
}

TEST_CASE("content_hash is FNV-1a 64 over the file bytes", "[eni][real]") {
    // Reference values computed with a separate Python FNV-1a implementation.
    CHECK(must_load(real_eni("elmo_eas_rocos_1slave.xml"))->content_hash == 0x80a93453e7eae278ull);
    CHECK(must_load(real_eni("advantech_empty_ring_0slaves.xml"))->content_hash == 0x51d9a67754b7aa08ull);
}

}  // namespace
}  // namespace ecpair::eni
