// `ecpairctl eni FILE`: exit codes and the lines a person (or a script)
// looks for.

#include <sstream>

#include "eni_command.hpp"
#include "eni_test_files.hpp"

namespace ecpair::ctl {
namespace {

using eni::test::bad_eni;
using eni::test::extra_eni;
using eni::test::real_eni;

struct Run {
    int exit_code;
    std::string out;
    std::string err;
};

Run run(const std::vector<std::string>& args) {
    std::ostringstream out;
    std::ostringstream err;
    const int code = run_eni_command(args, out, err);
    return {code, out.str(), err.str()};
}

TEST_CASE("eni: a valid EC-Engineer file is summarised, with the LRW warning", "[eni][ctl]") {
    const auto r = run({real_eni("ecengineer_rocos_rdm_6slaves.xml")});
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.err.empty());
    CHECK_THAT(r.out, Catch::Contains("root      <EtherCATConfig> Version 1.3\n"));
    CHECK_THAT(r.out, Catch::Contains("master    Class-A Master\n"));
    CHECK_THAT(r.out, Catch::Contains("6 slave(s)\n"));
    // The header row and the first slave row line up; the name's newline is escaped.
    CHECK_THAT(r.out, Catch::Contains("  POS  PHYS  NAME                VENDOR      PRODUCT     REVISION    SERIAL"));
    CHECK_THAT(r.out, Catch::Contains("    0  1001  Slave_1001 [RDM\\n]  0x000000ab  0x00001030  0x00010003"));
    CHECK_THAT(r.out, Catch::Contains("init commands: 12 master, 288 slave register, 90 CoE\n"));
    CHECK_THAT(r.out, Catch::Contains("cyclic: cycle time 1000 us, 1 frame(s)\n"));
    CHECK_THAT(r.out, Catch::Contains("LRW   SAFEOP,OP        logical 0x10000000      96   18        0         0\n"));
    CHECK_THAT(r.out, Catch::Contains("warning: the cyclic frames use LRW (1 command(s)); cable redundancy refuses LRW"));
    CHECK_THAT(r.out, Catch::Contains("hot-connect groups: none\n"));
    CHECK_THAT(r.out, Catch::EndsWith("valid\n"));
}

TEST_CASE("eni: Hot-Connect groups and an LRD/LWR file", "[eni][ctl]") {
    const auto hc = run({extra_eni("hotconnect_groups_4slaves.xml")});
    INFO(hc.out << hc.err);
    CHECK(hc.exit_code == 0);
    CHECK_THAT(hc.out, Catch::Contains("2 hot-connect group(s)\n"));
    CHECK_THAT(hc.out, Catch::Contains("  HEAD POS  HEAD PHYS  GROUP         MEMBERS  IDENTIFY CMDS\n"
                                       "         1       1002  Gripper             2              2\n"
                                       "         3       1004  Tool changer        1              3\n"));

    const auto split = run({extra_eni("lrd_lwr_2slaves.xml")});
    INFO(split.out);
    CHECK(split.exit_code == 0);
    CHECK_THAT(split.out, Catch::Contains("cable redundancy: no LRW in the cyclic frames\n"));
    CHECK_THAT(split.out, !Catch::Contains("warning"));
    CHECK_THAT(split.out, Catch::Contains("inputs   2 bytes, 1 variable(s)\n"));
    CHECK_THAT(split.out, Catch::Contains("ref clock"));
    CHECK_THAT(split.out, Catch::Contains("CoE"));
}

TEST_CASE("eni: a passive end cap is listed apart from the ring's slaves", "[eni][ctl]") {
    const auto r = run({extra_eni("passive_end_cap_4slaves.xml")});
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.out, Catch::Contains("\n3 slave(s)\n"));
    CHECK_THAT(r.out, Catch::Contains("passive terminal (no ESC, not in the ring): Term 4 (EL9011) behind station 1003 port B "
                                      "product 0x23333052\n"));
}

TEST_CASE("eni: the 0-slave file is valid", "[eni][ctl]") {
    const auto r = run({real_eni("advantech_empty_ring_0slaves.xml")});
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.out, Catch::Contains("root      <EtherCATConfig> (no Version)\n"));
    CHECK_THAT(r.out, Catch::Contains("0 slave(s)\n"));
    CHECK_THAT(r.out, Catch::Contains("process image: not described\n"));
}

TEST_CASE("eni: an invalid file exits 2 with the located error on stderr", "[eni][ctl]") {
    const auto r = run({bad_eni("unknown_transition.xml")});
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    CHECK(r.err == "ecpairctl eni: " + bad_eni("unknown_transition.xml") +
                       ":109: /EtherCATConfig/Config/Slave[2]/InitCmds/InitCmd[2]/Transition[2]: unknown transition "
                       "code 'SX' (expected IP, PS, SO, SP, OP, OS, PI, SI, OI, IB, BI, II or PP)\n");
}

TEST_CASE("eni: wrong arguments exit 2 with usage, --help exits 0", "[eni][ctl]") {
    for (const auto& args : std::vector<std::vector<std::string>>{{}, {"a.xml", "b.xml"}, {"--verbose"}}) {
        const auto r = run(args);
        CHECK(r.exit_code == 2);
        CHECK(r.out.empty());
        CHECK_THAT(r.err, Catch::Contains("usage: ecpairctl eni FILE"));
    }
    const auto help = run({"--help"});
    CHECK(help.exit_code == 0);
    CHECK_THAT(help.out, Catch::StartsWith("usage: ecpairctl eni FILE"));
}

}  // namespace
}  // namespace ecpair::ctl
