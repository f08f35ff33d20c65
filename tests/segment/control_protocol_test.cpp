// The control request grammar: every command, and every way to get it wrong.

#include <array>

#include <catch2/catch.hpp>

#include "ecpair/sim/control_protocol.hpp"

using namespace ecpair::sim;

namespace {

ControlRequest parsed(std::string_view line) {
    const auto request = parse_control_request(line);
    if (!request) FAIL("'" << line << "' was refused: " << request.error().message);
    return *request;
}

std::string refusal(std::string_view line) {
    const auto request = parse_control_request(line);
    if (request) FAIL("'" << line << "' was accepted");
    return request.error().message;
}

}  // namespace

TEST_CASE("every control command parses", "[control]") {
    CHECK(parsed("status") == ControlRequest{ControlCommand::Status, 0, 0});
    CHECK(parsed("help") == ControlRequest{ControlCommand::Help, 0, 0});
    CHECK(parsed("power-off 3") == ControlRequest{ControlCommand::PowerOff, 3, 0});
    CHECK(parsed("power-on 3") == ControlRequest{ControlCommand::PowerOn, 3, 0});
    CHECK(parsed("break 0") == ControlRequest{ControlCommand::Break, 0, 0});
    CHECK(parsed("repair 5") == ControlRequest{ControlCommand::Repair, 5, 0});
    CHECK(parsed("insert-unknown 2") == ControlRequest{ControlCommand::InsertUnknown, 2, 0});
    CHECK(parsed("remove-unknown 2") == ControlRequest{ControlCommand::RemoveUnknown, 2, 0});
    CHECK(parsed("set-alias 4 4660") == ControlRequest{ControlCommand::SetAlias, 4, 4660});
    CHECK(parsed("set-id 1 0xBEEF") == ControlRequest{ControlCommand::SetId, 1, 0xBEEF});
    ControlRequest port_errors{ControlCommand::PortErrors, 3, 0};
    port_errors.port = 1;
    port_errors.count = 1'000'000;
    CHECK(parsed("port-errors 3 B 1000000") == port_errors);
}

TEST_CASE("blanks and a trailing CR are tolerated", "[control]") {
    CHECK(parsed("  break\t2  ") == ControlRequest{ControlCommand::Break, 2, 0});
    CHECK(parsed("status\r") == ControlRequest{ControlCommand::Status, 0, 0});
    CHECK(parsed("set-alias 1 0x0\r") == ControlRequest{ControlCommand::SetAlias, 1, 0});
}

TEST_CASE("bad requests are refused with a reason", "[control]") {
    CHECK(refusal("") == "empty request (try 'help')");
    CHECK(refusal("   ") == "empty request (try 'help')");
    CHECK(refusal("reboot") == "unknown command 'reboot' (try 'help')");
    CHECK(refusal("STATUS") == "unknown command 'STATUS' (try 'help')");
    CHECK(refusal("power-off") == "power-off takes 1 argument, got 0: power-off K");
    CHECK(refusal("status 1") == "status takes 0 arguments, got 1: status");
    CHECK(refusal("set-id 1") == "set-id takes 2 arguments, got 1: set-id K VALUE");
    CHECK(refusal("break 1 2 3") == "break takes 1 argument, got 3: break K");
    CHECK(refusal("break 1 2 3 4 5") == "too many words in 'break 1 2 3 4 5'");
    CHECK(refusal("break -1") == "break: K must be a decimal number in 0..65535, got '-1'");
    CHECK(refusal("break 0x2") == "break: K must be a decimal number in 0..65535, got '0x2'");
    CHECK(refusal("break 65536") == "break: K must be a decimal number in 0..65535, got '65536'");
    CHECK(refusal("break 99999999999999999999") ==
          "break: K must be a decimal number in 0..65535, got '99999999999999999999'");
    CHECK(refusal("set-alias 1 0x10000") ==
          "set-alias: VALUE must be a number in 0..65535 (decimal or 0x hex), got '0x10000'");
    CHECK(refusal("set-alias 1 0x") == "set-alias: VALUE must be a number in 0..65535 (decimal or 0x hex), got '0x'");
    CHECK(refusal("set-alias 1 12ab") ==
          "set-alias: VALUE must be a number in 0..65535 (decimal or 0x hex), got '12ab'");
}

TEST_CASE("control characters are shown escaped and long lines refused", "[control]") {
    CHECK(refusal(std::string_view("st\0tus", 6)) == "unknown command 'st\\x00tus' (try 'help')");
    CHECK(refusal("break \x1b[2J") == "break: K must be a decimal number in 0..65535, got '\\x1b[2J'");
    const std::string long_line(kMaxControlLineLength + 1, 'x');
    CHECK(refusal(long_line) == "request is 257 characters long; the limit is 256");
}

TEST_CASE("responses stay on one line", "[control]") {
    CHECK(control_ok() == "ok");
    CHECK(control_ok("slave 1 powered off") == "ok slave 1 powered off");
    CHECK(control_error("slave 2 is 'RDM\n'") == "error: slave 2 is 'RDM '");
    const std::string usage = control_usage();
    CHECK(usage.find('\n') == std::string::npos);
    CHECK_THAT(usage, Catch::Contains("set-alias K VALUE") && Catch::Contains("insert-unknown K"));
}

TEST_CASE("impair names a cable, a loss and a duplication share and a delay", "[control]") {
    const auto request = parsed("impair red 10 2 500");
    CHECK(request.command == ControlCommand::Impair);
    CHECK(request.red_side);
    CHECK(request.loss_percent == 10);
    CHECK(request.duplicate_percent == 2);
    CHECK(request.delay_us == 500);
    CHECK_FALSE(parsed("impair main 0 0 0").red_side);
    CHECK(refusal("impair left 1 1 1") == "impair: SIDE must be main or red, got 'left'");
    CHECK(refusal("impair main 101 0 0") == "impair: LOSS% and DUP% must be 0..100, got '101' '0'");
    CHECK(refusal("impair main 0 0 200000") == "impair: DELAY_US must be 0..100000, got '200000'");
    CHECK(refusal("impair main 1 1") ==
          "impair takes 4 arguments, got 3: impair main|red LOSS% DUP% DELAY_US");
}

TEST_CASE("the Hot-Connect commands name a group, a slave, a port and a state", "[control]") {
    CHECK(parsed("group-off 2").command == ControlCommand::GroupOff);
    CHECK(parsed("group-off 2").group == 2);
    CHECK(parsed("group-on 1").command == ControlCommand::GroupOn);
    CHECK(parsed("unplug-group 3").group == 3);
    const auto plug = parsed("plug-group 1 4 D");
    CHECK(plug.command == ControlCommand::PlugGroup);
    CHECK(plug.group == 1);
    CHECK(plug.at == 4);
    CHECK(plug.port == 3);
    const auto unknown = parsed("plug-unknown 2 C");
    CHECK(unknown.command == ControlCommand::PlugUnknown);
    CHECK(unknown.position == 2);
    CHECK(unknown.port == 2);
    const auto duplicate = parsed("plug-duplicate 5 1 2");
    CHECK(duplicate.command == ControlCommand::PlugDuplicate);
    CHECK(duplicate.position == 5);
    CHECK(duplicate.at == 1);
    CHECK(duplicate.port == 2);
    CHECK(parsed("refuse-state 3 SAFEOP").state == 4);
    CHECK(parsed("refuse-state 3 none").state == 0);
    const auto selector = parsed("set-selector 2 0x65");
    CHECK(selector.command == ControlCommand::SetSelector);
    CHECK(selector.value == 0x65);
    CHECK(refusal("plug-group 1 4 E") == "plug-group: PORT must be A, B, C or D (or 0..3), got 'E'");
    CHECK(refusal("plug-group x 4 D") == "plug-group: N must be a decimal number in 0..65535, got 'x'");
    CHECK(refusal("plug-duplicate 1 x D") == "plug-duplicate: J must be a decimal number in 0..65535, got 'x'");
    CHECK(refusal("refuse-state 1 BOOT") == "refuse-state: STATE must be PREOP, SAFEOP, OP or none, got 'BOOT'");
    CHECK(refusal("plug-group 1 4 D 5") == "plug-group takes 3 arguments, got 4: plug-group N K PORT");
    const std::string usage = control_usage();
    CHECK_THAT(usage, Catch::Contains("plug-group N K PORT") && Catch::Contains("impair main|red LOSS% DUP% DELAY_US"));
}

TEST_CASE("emergency takes a code and optionally a register and up to five data bytes, foe-password and foe-busy",
          "[control]") {
    const auto plain = parsed("emergency 2 0x8130");
    CHECK(plain.command == ControlCommand::Emergency);
    CHECK(plain.position == 2);
    CHECK(plain.value == 0x8130);
    CHECK(plain.error_register == 0);
    CHECK(plain.emergency_data == std::array<std::uint8_t, 5>{});
    const auto full = parsed("emergency 1 16912 0x11 0102030405");
    CHECK(full.value == 16912);
    CHECK(full.error_register == 0x11);
    CHECK(full.emergency_data == std::array<std::uint8_t, 5>{1, 2, 3, 4, 5});
    CHECK(parsed("emergency 1 1 2 0xaabb").emergency_data == std::array<std::uint8_t, 5>{0xaa, 0xbb, 0, 0, 0});
    CHECK(refusal("emergency 1") == "emergency takes 2 to 4 arguments, got 1: emergency K CODE [REG [DATA]]");
    CHECK(refusal("emergency 1 70000") ==
          "emergency: CODE must be a number in 0..65535 (decimal or 0x hex), got '70000'");
    CHECK(refusal("emergency 1 1 256") == "emergency: REG must be a number in 0..255 (decimal or 0x hex), got '256'");
    CHECK(refusal("emergency 1 1 1 010203040506") ==
          "emergency: DATA must be 1 to 5 bytes as hex digits (0102030405), got '010203040506'");
    CHECK(refusal("emergency 1 1 1 0g") == "emergency: DATA must be 1 to 5 bytes as hex digits (0102030405), got '0g'");

    const auto password = parsed("foe-password 3 0xDEADBEEF");
    CHECK(password.command == ControlCommand::FoePassword);
    CHECK(password.position == 3);
    CHECK(password.password == 0xDEADBEEF);
    CHECK(refusal("foe-password 3 x") ==
          "foe-password: PASSWORD must be a number in 0..4294967295 (decimal or 0x hex), got 'x'");
    const auto busy = parsed("foe-busy 2 5");
    CHECK(busy.command == ControlCommand::FoeBusy);
    CHECK(busy.value == 5);
}
