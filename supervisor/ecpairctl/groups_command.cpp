// `ecpairctl groups [--json]`: the Hot-Connect groups of a running ecpaird
// with their members and presence, the mismatches (numbered for block-node
// --mismatch N) and the ports block-node closed.

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "exit_codes.hpp"
#include "hot_connect_view.hpp"

namespace ecpair::ctl {

namespace po = boost::program_options;

void print_hot_connect_groups(std::ostream& out, const control::HotConnectGroupsReply& r) {
    const auto& s = r.summary();
    fmt::print(out, "Hot-Connect: {}, mode {}, border close {}; {} of {} optional group(s) present; {} slave(s) on the bus; "
                    "{} topology change(s){}\n",
               s.state(), s.mode(), s.border_close() ? "on" : "off", s.groups_present(), s.groups(), s.slaves_on_bus(),
               s.changes(), s.last_result().empty() ? std::string() : fmt::format(", the last: {}", s.last_result()));
    for (const auto& g : r.groups()) {
        fmt::print(out, "\ngroup {} '{}': {}{}{}\n", g.number(), g.name(), g.status(), g.floating() ? ", floating" : "",
                   g.number() == 0 ? std::string() : fmt::format(", identification {}", g.identification()));
        fmt::print(out, "  {:>5}  {:<7}  {:<8}  {:<11}  {}\n", "SLAVE", "STATION", "PRESENT", "STATE", "NAME");
        for (const auto& m : g.members()) {
            fmt::print(out, "  {:>5}  {:<7}  {:<8}  {:<11}  {}\n", m.slave(), m.station(), m.present() ? "yes" : "no",
                       m.al_state(), m.name());
        }
    }
    if (!r.mismatches().empty()) {
        fmt::print(out, "\n{} mismatch(es) (block-node --mismatch N):\n", r.mismatches_size());
        for (int i = 0; i < r.mismatches_size(); ++i) fmt::print(out, "  [{}] {}\n", i, r.mismatches(i).text());
    }
    if (!r.blocked().empty()) {
        fmt::print(out, "\nblocked ports (open-blocked-ports):\n");
        for (const auto& p : r.blocked()) fmt::print(out, "  station {} port {}\n", p.station(), p.port());
    }
}

void write_hot_connect_summary_json(JsonWriter& json, const control::HotConnectSummary& s) {
    json.key("state").value(s.state()).key("mode").value(s.mode()).key("border_close").value(s.border_close());
    json.key("groups").value(s.groups()).key("groups_present").value(s.groups_present());
    json.key("slaves_on_bus").value(s.slaves_on_bus()).key("changes").value(s.changes());
    json.key("last_result");
    if (s.last_result().empty()) {
        json.null();
    } else {
        json.value(s.last_result());
    }
    json.key("mismatches").value(s.mismatches());
}

namespace {

void optional_number(JsonWriter& json, std::string_view key, bool has, std::uint32_t value) {
    json.key(key);
    if (has) {
        json.value(value);
    } else {
        json.null();
    }
}

}  // namespace

void write_hot_connect_groups_json(JsonWriter& json, const control::HotConnectGroupsReply& r) {
    json.begin_object();
    json.key("summary").begin_object();
    write_hot_connect_summary_json(json, r.summary());
    json.end_object();
    json.key("groups").begin_array();
    for (const auto& g : r.groups()) {
        json.begin_object().key("number").value(g.number()).key("name").value(g.name());
        json.key("mandatory").value(g.number() == 0).key("floating").value(g.floating());
        json.key("identification").value(g.identification()).key("status").value(g.status());
        json.key("members").begin_array();
        for (const auto& m : g.members()) {
            json.begin_object().key("slave").value(m.slave()).key("name").value(m.name());
            json.key("station").value(m.station()).key("present").value(m.present());
            json.key("al_state").value(m.al_state()).end_object();
        }
        json.end_array().end_object();
    }
    json.end_array();
    json.key("mismatches").begin_array();
    for (const auto& m : r.mismatches()) {
        json.begin_object().key("position").value(m.position()).key("kind").value(m.kind());
        optional_number(json, "previous_station", m.has_previous_station(), m.previous_station());
        json.key("previous_port").value(m.previous_port());
        optional_number(json, "previous_position", m.has_previous_position(), m.previous_position());
        optional_number(json, "configured_station", m.has_configured_station(), m.configured_station());
        json.key("found_vendor").value(m.found_vendor()).key("found_product").value(m.found_product());
        json.key("found_revision").value(m.found_revision()).key("found_serial").value(m.found_serial());
        json.key("found_station").value(m.found_station());
        json.key("identification_error").value(m.identification_error());
        json.key("identification_ado").value(m.identification_ado());
        optional_number(json, "value_read", m.has_value_read(), m.value_read());
        json.key("value_expected").value(m.value_expected()).key("text").value(m.text()).end_object();
    }
    json.end_array();
    json.key("blocked").begin_array();
    for (const auto& p : r.blocked()) {
        json.begin_object().key("station").value(p.station()).key("port").value(p.port()).end_object();
    }
    json.end_array();
    json.end_object();
}

int run_groups_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    po::options_description options("ecpairctl groups options");
    add_socket_options(options, sockets);
    options.add_options()("json", "one JSON object instead of the table");
    po::variables_map vm;
    const std::string usage = "ecpairctl groups [--socket PATH] [--json]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "groups", usage, out, err)) return *rc;
    control::Request request;
    request.mutable_hc_groups();
    auto response = call_daemon(sockets.path(), request, err);
    if (!response) return response.error();
    if (vm.count("json") != 0) {
        JsonWriter writer;
        write_hot_connect_groups_json(writer, response->hc_groups());
        fmt::print(out, "{}\n", writer.str());
    } else {
        print_hot_connect_groups(out, response->hc_groups());
    }
    return kExitOk;
}

}  // namespace ecpair::ctl
