// ecpairctl's commands that talk to a daemon, run in-process against an
// operator socket served by a fake handler: the table, --json parsed back by
// protobuf's JSON parser, the pair view and its verdicts, watch, the exit
// codes and the one-line errors.

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <fstream>
#include <limits>
#include <sstream>
#include <fmt/format.h>

#include "control_server_fixture.hpp"
#include "ctl_commands.hpp"
#include "exit_codes.hpp"
#include "json_writer.hpp"

using namespace ecpair::control;
using namespace ecpair::control::test;
using namespace ecpair::ctl;
using google::protobuf::Struct;
using google::protobuf::Value;

namespace {

struct Run {
    int code;
    std::string out;
    std::string err;
};

Run run(RunCommand command, const CommandArgs& args) {
    std::ostringstream out;
    std::ostringstream err;
    const int code = command(args, out, err);
    return {code, out.str(), err.str()};
}

Struct parse_json(const std::string& text) {
    Struct parsed;
    const auto status = google::protobuf::util::JsonStringToMessage(text, &parsed);
    if (!status.ok()) FAIL("not JSON: " << status.ToString() << "\n" << text);
    return parsed;
}

const Value& field(const Struct& s, const std::string& name) {
    const auto it = s.fields().find(name);
    if (it == s.fields().end()) FAIL("no key '" << name << "'");
    return it->second;
}

StatusReply member(const std::string& name, const std::string& role, bool partner_seen) {
    StatusReply s;
    s.set_name(name);
    s.set_master_state("OP");
    s.set_target_state("OP");
    s.set_ring_state("closed");
    s.set_main_link_up(true);
    s.set_red_link_up(true);
    s.set_cycle_time_us(1000);
    s.mutable_timing()->set_cycles(123456);
    s.mutable_timing()->set_late(2);
    s.mutable_counters()->set_frames_sent(999);
    auto* r = s.mutable_redundancy();
    r->set_enabled(true);
    r->set_red_state(role);
    r->set_partner_seen(partner_seen);
    r->set_mirrored_cycle(role == "INACTIVE" ? 123450 : 0);
    s.mutable_link_guard()->set_enabled(true);
    s.mutable_link_guard()->set_running(true);
    s.mutable_link_guard()->set_hang_timeout_ms(50);
    for (std::uint32_t i = 0; i < 2; ++i) {
        auto* slave = s.add_slaves();
        slave->set_position(i);
        slave->set_name(i == 0 ? "EK1100 \"coupler\"" : "EL2008");
        slave->set_station_address(1001 + i);
        slave->set_present(true);
        slave->set_al_state("OP");
    }
    return s;
}

}  // namespace

TEST_CASE("ecpairctl status: a readable table of the daemon", "[ctl]") {
    const auto reply = member("m1", "ACTIVE", true);
    ServerFixture f({}, &reply);
    const auto r = run(run_status_command, {"--socket", f.path});
    REQUIRE(r.code == kExitOk);
    CHECK(r.err.empty());
    INFO(r.out);
    CHECK(r.out.find("m1: master OP (target OP), cycle 1000 µs\n") == 0);
    CHECK(r.out.find("  links: MAIN up, RED up; ring closed\n") != std::string::npos);
    CHECK(r.out.find("  cycles 123456 (2 late") != std::string::npos);
    CHECK(r.out.find("  redundancy: ACTIVE, partner seen\n") != std::string::npos);
    CHECK(r.out.find("  link guard: running, links up; links down after 50 ms standing still") != std::string::npos);
    CHECK(r.out.find("  operator socket: 1 client(s) of 2048") != std::string::npos);
    CHECK(r.out.find("    1  1002     yes       OP           EL2008\n") != std::string::npos);
}

TEST_CASE("ecpairctl status --json: one object with the keys scripts read, parsed back", "[ctl]") {
    auto reply = member("m2", "INACTIVE", true);
    reply.set_sequence_error("");
    ServerFixture f({}, &reply);
    const auto r = run(run_status_command, {"--socket", f.path, "--json"});
    REQUIRE(r.code == kExitOk);
    REQUIRE(r.out.back() == '\n');
    CHECK(r.out.find('\n') == r.out.size() - 1);  // one line
    const auto json = parse_json(r.out);
    CHECK(field(json, "name").string_value() == "m2");
    CHECK(field(json, "red_state").string_value() == "INACTIVE");
    CHECK(field(json, "master_state").string_value() == "OP");
    CHECK(field(json, "partner_seen").bool_value());
    CHECK(field(json, "forced_standby").kind_case() == Value::kBoolValue);
    CHECK_FALSE(field(json, "forced_standby").bool_value());
    CHECK(field(json, "sequence_error").kind_case() == Value::kNullValue);
    CHECK(field(field(json, "cycles").struct_value(), "count").number_value() == 123456);
    CHECK(field(field(json, "redundancy").struct_value(), "mirrored_cycle").number_value() == 123450);
    CHECK(field(field(json, "link_guard").struct_value(), "hang_timeout_ms").number_value() == 50);
    CHECK(field(field(json, "operator_socket").struct_value(), "clients").number_value() == 1);
    const auto& slaves = field(json, "slaves").list_value();
    REQUIRE(slaves.values_size() == 2);
    CHECK(field(slaves.values(0).struct_value(), "name").string_value() == "EK1100 \"coupler\"");
    CHECK(field(slaves.values(1).struct_value(), "station_address").number_value() == 1002);
}

TEST_CASE("ecpairctl status: forced standby comes from the supervisor's status", "[ctl]") {
    const auto active = member("m1", "ACTIVE", true);
    auto forced = member("m2", "INACTIVE", true);
    forced.mutable_supervisor()->set_forced_standby(true);
    ServerFixture fa({}, &active);
    ServerFixture fb({}, &forced);
    const auto json = parse_json(run(run_status_command, {"--socket", fb.path, "--json"}).out);
    CHECK(field(json, "forced_standby").bool_value());
    CHECK(run(run_status_command, {"--socket", fb.path}).out.find("  redundancy: INACTIVE, partner seen, mirrored cycle 123450, FORCED STANDBY\n") !=
          std::string::npos);
    CHECK(run(run_status_command, {"--socket", fa.path, "--socket", fb.path}).out.find(
              "verdict: m1 ACTIVE; m2 INACTIVE, forced standby\n") != std::string::npos);
}

TEST_CASE("ecpairctl status --json: a single master has no red_state", "[ctl]") {
    StatusReply reply;
    reply.set_name("solo");
    reply.set_master_state("SAFEOP");
    ServerFixture f({}, &reply);
    const auto json = parse_json(run(run_status_command, {"--socket", f.path, "--json"}).out);
    CHECK(field(json, "red_state").kind_case() == Value::kNullValue);
    CHECK_FALSE(field(json, "partner_seen").bool_value());
    CHECK_FALSE(field(field(json, "link_guard").struct_value(), "enabled").bool_value());
}

TEST_CASE("ecpairctl status with two sockets: the pair view and its verdict", "[ctl]") {
    SECTION("one ACTIVE, one hot standby") {
        const auto a = member("m1", "ACTIVE", true);
        const auto b = member("m2", "INACTIVE", true);
        ServerFixture fa({}, &a);
        ServerFixture fb({}, &b);
        const auto r = run(run_status_command, {"--socket", fa.path, "--socket", fb.path});
        REQUIRE(r.code == kExitOk);
        INFO(r.out);
        CHECK(r.out.find("pair          m1") == 0);
        CHECK(r.out.find("role          ACTIVE") != std::string::npos);
        CHECK(r.out.find("slaves in OP  2/2") != std::string::npos);
        CHECK(r.out.find("verdict: m1 ACTIVE; m2 INACTIVE, hot standby (mirrored cycle 123450)\n") != std::string::npos);

        const auto json = parse_json(run(run_status_command, {"--socket", fa.path, "--socket", fb.path, "--json"}).out);
        CHECK(field(json, "active").string_value() == "m1");
        CHECK(field(json, "active_count").number_value() == 1);
        const auto& members = field(json, "members").list_value();
        REQUIRE(members.values_size() == 2);
        const auto& second = members.values(1).struct_value();
        CHECK(field(second, "reachable").bool_value());
        CHECK(field(field(second, "status").struct_value(), "red_state").string_value() == "INACTIVE");
    }
    SECTION("two ACTIVE") {
        const auto a = member("m1", "ACTIVE", false);
        const auto b = member("m2", "ACTIVE", false);
        ServerFixture fa({}, &a);
        ServerFixture fb({}, &b);
        const auto r = run(run_status_command, {"--socket", fa.path, "--socket", fb.path});
        CHECK(r.code == kExitOk);
        CHECK(r.out.find("verdict: TWO ACTIVE masters: m1 and m2 both drive the bus\n") != std::string::npos);
        const auto json = parse_json(run(run_status_command, {"--socket", fa.path, "--socket", fb.path, "--json"}).out);
        CHECK(field(json, "active").kind_case() == Value::kNullValue);
        CHECK(field(json, "active_count").number_value() == 2);
    }
    SECTION("none ACTIVE") {
        const auto a = member("m1", "INACTIVE", false);
        const auto b = member("m2", "INACTIVE", false);
        ServerFixture fa({}, &a);
        ServerFixture fb({}, &b);
        CHECK(run(run_status_command, {"--socket", fa.path, "--socket", fb.path}).out.find(
                  "verdict: NO ACTIVE master: nobody drives the slaves\n") != std::string::npos);
    }
    SECTION("a standby that is not hot says why") {
        const auto a = member("m1", "ACTIVE", true);
        auto b = member("m2", "INACTIVE", true);
        b.mutable_redundancy()->set_partner_mismatch("ENI");
        ServerFixture fa({}, &a);
        ServerFixture fb({}, &b);
        CHECK(run(run_status_command, {"--socket", fa.path, "--socket", fb.path}).out.find(
                  "verdict: m1 ACTIVE; m2 INACTIVE, NOT a standby: partner differs (ENI)\n") != std::string::npos);
    }
    SECTION("a member that cannot be reached") {
        const auto a = member("m1", "ACTIVE", false);
        ServerFixture fa({}, &a);
        const std::string gone = (fa.dir / "m2.sock").string();
        const auto r = run(run_status_command, {"--socket", fa.path, "--socket", gone});
        CHECK(r.code == kExitUnreachable);
        CHECK(r.out.find("verdict: m1 ACTIVE; unreachable: " + gone + ": no such socket") != std::string::npos);
        CHECK(r.err == "ecpairctl: " + gone +
                           ": no such socket: is ecpaird running? (--socket PATH or --name NAME picks another)\n");
        const auto json = parse_json(run(run_status_command, {"--socket", fa.path, "--socket", gone, "--json"}).out);
        const auto& second = field(json, "members").list_value().values(1).struct_value();
        CHECK_FALSE(field(second, "reachable").bool_value());
        CHECK(field(second, "error").string_value().find("no such socket") != std::string::npos);
    }
}

TEST_CASE("ecpairctl watch: redraws the status with the latest events, then stops after --count", "[ctl]") {
    const auto reply = member("m1", "ACTIVE", true);
    ServerFixture f({}, &reply);
    f.on_io([&f] {
        EventMessage event;
        event.set_kind("line-break");
        event.set_text("cycle 7: line break after slave 2");
        event.set_unix_time_ms(1'700'000'000'123);
        f.server->publish(event);
    });
    const auto r = run(run_watch_command, {"--socket", f.path, "--interval", "0.1", "--count", "3"});
    REQUIRE(r.code == kExitOk);
    INFO(r.out);
    std::size_t views = 0;
    for (auto at = r.out.find("--- "); at != std::string::npos; at = r.out.find("--- ", at + 1)) ++views;
    CHECK(views == 3);
    CHECK(r.out.find("m1: master OP") != std::string::npos);
    CHECK(r.out.find(".123 line-break cycle 7: line break after slave 2") != std::string::npos);
    CHECK(r.out.find("\x1b[2J") == std::string::npos);  // not a terminal: no clearing
}

TEST_CASE("ecpairctl: exit codes and one-line errors", "[ctl]") {
    ServerFixture f;
    SECTION("the daemon refuses: 1, with its reason") {
        const auto r = run(run_red_state_command, {"--socket", f.path, "ACTIVE"});
        CHECK(r.code == kExitRefused);
        CHECK(r.err == "ecpairctl: " + f.path + ": not a pair\n");
    }
    SECTION("accepted: 0") {
        const auto r = run(run_state_command, {"--socket", f.path, "SAFEOP"});
        CHECK(r.code == kExitOk);
        CHECK(r.out == "SAFEOP requested\n");
    }
    SECTION("bad arguments: 2, one line") {
        const auto r = run(run_status_command, {"--socket", f.path, "--jsn"});
        CHECK(r.code == kExitUsage);
        CHECK(r.err.find("ecpairctl status: unrecognised option '--jsn' (usage: ecpairctl status") == 0);
        CHECK(r.err.find('\n') == r.err.size() - 1);
        const auto missing = run(run_state_command, {"--socket", f.path});
        CHECK(missing.code == kExitUsage);
        CHECK(missing.err.find('\n') == missing.err.size() - 1);
        CHECK(run(run_status_command, {"--socket", "a", "--socket", "b", "--socket", "c"}).code == kExitUsage);
    }
    SECTION("no daemon: 3") {
        const auto r = run(run_status_command, {"--socket", (f.dir / "nobody.sock").string()});
        CHECK(r.code == kExitUnreachable);
        CHECK(r.err.find("no such socket: is ecpaird running?") != std::string::npos);
        CHECK(run(run_events_command, {"--socket", (f.dir / "nobody.sock").string(), "--for", "1"}).code ==
              kExitUnreachable);
    }
    SECTION("a socket nobody listens on: 3") {
        const auto stale = (f.dir / "stale.sock").string();
        const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        std::memcpy(address.sun_path, stale.c_str(), stale.size() + 1);
        REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0);
        ::close(fd);  // bound, never listened: a left-over socket file
        const auto r = run(run_status_command, {"--socket", stale});
        CHECK(r.code == kExitUnreachable);
        CHECK(r.err == "ecpairctl: " + stale + ": nobody listens there (ecpaird stopped or crashed)\n");
    }
}

TEST_CASE("ecpairctl run as another user: 4, naming the socket's mode and group", "[ctl]") {
    if (::geteuid() != 0) {
        WARN("needs root to run ecpairctl as another user");
        return;
    }
    SocketSettings settings;
    settings.mode = 0660;
    ServerFixture f(settings);
    std::filesystem::permissions(f.dir.path(), std::filesystem::perms::all);
    const std::string out = (f.dir / "out.txt").string();
    const std::string command = fmt::format("setpriv --reuid=nobody --regid=nogroup --clear-groups {} status --socket {} 2>{}",
                                            ECPAIR_ECPAIRCTL, f.path, out);
    const int status = std::system(command.c_str());
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == kExitDenied);
    std::ifstream in(out);
    std::string line;
    std::getline(in, line);
    CHECK(line.find("ecpairctl: " + f.path + ": permission denied: the socket is mode 660, group root") == 0);
}

TEST_CASE("the JSON writer escapes strings and keeps invalid UTF-8 out", "[ctl]") {
    JsonWriter w;
    w.begin_object()
        .key("quote")
        .value("a\"b\\c\nd\x01")
        .key("latin1")
        .value("caf\xe9")
        .key("utf8")
        .value("µs")
        .key("list")
        .begin_array()
        .value(std::uint64_t{18446744073709551615ull})
        .value(-3)
        .value(0.5)
        .value(std::numeric_limits<double>::infinity())
        .null()
        .value(true)
        .end_array()
        .key("empty")
        .begin_object()
        .end_object()
        .end_object();
    CHECK(w.str() ==
          "{\"quote\":\"a\\\"b\\\\c\\nd\\u0001\",\"latin1\":\"caf\xEF\xBF\xBD\",\"utf8\":\"µs\","
          "\"list\":[18446744073709551615,-3,0.5,null,null,true],\"empty\":{}}");
    parse_json(w.str());
}

namespace {

HotConnectGroupsReply two_groups() {
    HotConnectGroupsReply r;
    auto* s = r.mutable_summary();
    s->set_state("idle");
    s->set_mode("automatic");
    s->set_groups(1);
    s->set_groups_present(0);
    s->set_slaves_on_bus(3);
    s->set_changes(2);
    s->set_last_result("groups refused (a mismatch)");
    s->set_mismatches(1);
    auto* mandatory = r.add_groups();
    mandatory->set_number(0);
    mandatory->set_name("mandatory");
    mandatory->set_identification("none");
    mandatory->set_status("present");
    auto* coupler = mandatory->add_members();
    coupler->set_slave(0);
    coupler->set_name("EK1100");
    coupler->set_station(1001);
    coupler->set_present(true);
    coupler->set_al_state("OP");
    auto* tool = r.add_groups();
    tool->set_number(1);
    tool->set_name("Tool changer");
    tool->set_floating(true);
    tool->set_identification("station alias 101");
    tool->set_status("absent");
    auto* io = tool->add_members();
    io->set_slave(3);
    io->set_name("EL1008");
    io->set_station(1004);
    io->set_present(false);
    io->set_al_state("?");
    auto* m = r.add_mismatches();
    m->set_position(3);
    m->set_kind("unexpected");
    m->set_previous_station(1001);
    m->set_previous_port("C");
    m->set_found_vendor(0x0BADC0DE);
    m->set_text("position 3: an unexpected slave at station 1001 port C");
    auto* p = r.add_blocked();
    p->set_station(1002);
    p->set_port("D");
    return r;
}

}  // namespace

TEST_CASE("ecpairctl groups: the groups, their members, the mismatches and blocked ports", "[ctl][hotconnect]") {
    ServerFixture f;
    f.on_io([&f] { f.handler.hc_groups = two_groups(); });
    SECTION("as a table") {
        const auto r = run(run_groups_command, {"--socket", f.path});
        INFO(r.out << r.err);
        CHECK(r.code == kExitOk);
        CHECK_THAT(r.out, Catch::Contains("Hot-Connect: idle, mode automatic, border close off; 0 of 1 optional group(s)") &&
                              Catch::Contains("group 1 'Tool changer': absent, floating, identification station alias 101") &&
                              Catch::Contains("[0] position 3: an unexpected slave") &&
                              Catch::Contains("station 1002 port D"));
    }
    SECTION("as JSON") {
        const auto r = run(run_groups_command, {"--socket", f.path, "--json"});
        REQUIRE(r.code == kExitOk);
        const auto json = parse_json(r.out);
        CHECK(field(field(json, "summary").struct_value(), "groups").number_value() == 1);
        CHECK(field(field(json, "summary").struct_value(), "last_result").string_value() == "groups refused (a mismatch)");
        const auto& groups = field(json, "groups").list_value();
        REQUIRE(groups.values_size() == 2);
        CHECK(field(groups.values(0).struct_value(), "mandatory").bool_value());
        const auto& tool = groups.values(1).struct_value();
        CHECK(field(tool, "status").string_value() == "absent");
        CHECK_FALSE(field(field(tool, "members").list_value().values(0).struct_value(), "present").bool_value());
        const auto& mismatch = field(json, "mismatches").list_value().values(0).struct_value();
        CHECK(field(mismatch, "previous_station").number_value() == 1001);
        CHECK(field(mismatch, "value_read").kind_case() == Value::kNullValue);
        CHECK(field(field(json, "blocked").list_value().values(0).struct_value(), "port").string_value() == "D");
    }
}

TEST_CASE("ecpairctl status: a Hot-Connect line and a hot_connect object", "[ctl][hotconnect]") {
    auto s = member("m1", "ACTIVE", true);
    *s.mutable_hot_connect() = two_groups().summary();
    ServerFixture f({}, &s);
    const auto table = run(run_status_command, {"--socket", f.path});
    CHECK_THAT(table.out, Catch::Contains("hot-connect: idle, mode automatic; 0 of 1 optional group(s) present") &&
                              Catch::Contains("1 MISMATCH(ES) (ecpairctl groups)"));
    const auto r = run(run_status_command, {"--socket", f.path, "--json"});
    REQUIRE(r.code == kExitOk);
    const auto json = parse_json(r.out);
    const auto& h = field(json, "hot_connect").struct_value();
    CHECK(field(h, "mode").string_value() == "automatic");
    CHECK(field(h, "slaves_on_bus").number_value() == 3);
}

TEST_CASE("ecpairctl's Hot-Connect operations send their request and keep the exit codes", "[ctl][hotconnect]") {
    ServerFixture f;
    SECTION("refused: 1, with the daemon's code") {
        const auto r = run(run_accept_command, {"--socket", f.path});
        CHECK(r.code == kExitRefused);
        CHECK(r.err == "ecpairctl: " + f.path + ": InvalidState: no topology change waits for an accept\n");
    }
    SECTION("accepted: 0") {
        f.on_io([&f] {
            f.handler.hc_refusal.clear();
            auto* p = f.handler.hc_ports.add_ports();
            p->set_station(1001);
            p->set_port("C");
        });
        CHECK(run(run_accept_command, {"--socket", f.path}).code == kExitOk);
        CHECK(f.on_io([&f] { return f.handler.last_hc_request.has_hc_accept(); }));
        CHECK(run(run_topology_change_command, {"--socket", f.path}).code == kExitOk);
        CHECK(f.on_io([&f] { return f.handler.last_hc_request.has_hc_force(); }));
        const auto blocked = run(run_block_node_command, {"--socket", f.path, "--mismatch", "2"});
        CHECK(blocked.code == kExitOk);
        CHECK(blocked.out == "station 1001 port C closed: what hangs behind it is cut off\n");
        CHECK(f.on_io([&f] { return f.handler.last_hc_request.hc_block_node().mismatch(); }) == 2);
        CHECK(run(run_open_blocked_ports_command, {"--socket", f.path}).out == "station 1001 port C open again\n");
        CHECK(run(run_port_command, {"--socket", f.path, "1002", "D", "closed"}).out == "station 1002 port D: closed\n");
        const auto port = f.on_io([&f] { return f.handler.last_hc_request.hc_set_port(); });
        CHECK(port.station() == 1002);
        CHECK(port.port() == "D");
        CHECK(port.setting() == "closed");
        const auto alias = run(run_alias_command, {"--socket", f.path, "set", "1004", "0x65"});
        CHECK(alias.code == kExitOk);
        CHECK_THAT(alias.out, Catch::Contains("SII station alias 101 (was 7)"));
        CHECK(f.on_io([&f] { return f.handler.last_hc_request.hc_set_alias().alias(); }) == 101);
    }
    SECTION("bad arguments: 2, one line") {
        for (const auto& r : {run(run_block_node_command, {"--socket", f.path, "--mismatch", "1", "--station", "2"}),
                              run(run_alias_command, {"--socket", f.path, "get", "1", "2"}),
                              run(run_alias_command, {"--socket", f.path, "set", "1", "70000"}),
                              run(run_port_command, {"--socket", f.path, "1001"})}) {
            CHECK(r.code == kExitUsage);
            CHECK(r.err.find('\n') == r.err.size() - 1);
        }
    }
    SECTION("no daemon: 3") {
        CHECK(run(run_groups_command, {"--socket", (f.dir / "nobody.sock").string()}).code == kExitUnreachable);
    }
}
