#include "hot_connect_commands.hpp"

#include <ostream>

#include <boost/program_options.hpp>
#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ecpair/control/control_client.hpp"

namespace ecpair::ctl {
namespace {

namespace po = boost::program_options;

constexpr int kOk = 0;
constexpr int kRefused = 1;
constexpr int kUsage = 2;
constexpr int kUnreachable = 3;

struct Call {
    std::string socket;
    std::string name = "ecpaird";
    std::string path() const { return socket.empty() ? fmt::format("/run/ecpair/{}.sock", name) : socket; }
};

// Parses the options common to every daemon command plus `extra`; nullopt to go on.
std::optional<int> parse(const std::vector<std::string>& args, Call& call, po::options_description& extra,
                         const po::positional_options_description& positional, po::variables_map& vm,
                         const std::string& usage, std::ostream& out, std::ostream& err) {
    po::options_description options("options");
    options.add_options()
        ("help,h", "this text")
        ("socket,s", po::value(&call.socket), "operator socket of the daemon")
        ("name,n", po::value(&call.name), "daemon name: the socket is /run/ecpair/NAME.sock (default ecpaird)");
    options.add(extra);
    try {
        po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
        if (vm.count("help") != 0) {
            fmt::print(out, "usage: {}\n{}", usage, fmt::streamed(options));
            return kOk;
        }
        po::notify(vm);
    } catch (const po::error& e) {
        fmt::print(err, "ecpairctl: {}\nusage: {}\n", e.what(), usage);
        return kUsage;
    }
    return std::nullopt;
}

Expected<control::Response, int> send(const Call& call, const control::Request& request, std::ostream& err) {
    auto response = control::call(call.path(), request);
    if (!response) {
        fmt::print(err, "ecpairctl: {}\n", response.error().message);
        return unexpected(kUnreachable);
    }
    if (!response->ok()) {
        fmt::print(err, "ecpairctl: {}\n", response->error());
        return unexpected(kRefused);
    }
    return std::move(*response);
}

void print_groups(std::ostream& out, const control::HotConnectGroupsReply& r) {
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

int groups(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Call call;
    po::options_description extra;
    po::variables_map vm;
    if (auto rc = parse(args, call, extra, {}, vm, "ecpairctl groups [--socket PATH]", out, err)) return *rc;
    control::Request request;
    request.mutable_hc_groups();
    auto response = send(call, request, err);
    if (!response) return response.error();
    print_groups(out, response->hc_groups());
    return kOk;
}

int simple(const std::vector<std::string>& args, const std::string& usage, std::ostream& out, std::ostream& err,
           const std::function<void(control::Request&)>& fill, const std::string& done) {
    Call call;
    po::options_description extra;
    po::variables_map vm;
    if (auto rc = parse(args, call, extra, {}, vm, usage, out, err)) return *rc;
    control::Request request;
    fill(request);
    auto response = send(call, request, err);
    if (!response) return response.error();
    fmt::print(out, "{}\n", done);
    return kOk;
}

int block_node(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Call call;
    std::uint32_t mismatch = 0;
    std::uint32_t station = 0;
    po::options_description extra;
    extra.add_options()
        ("mismatch", po::value(&mismatch), "the mismatch (as `ecpairctl groups` numbers them; default: the first)")
        ("station", po::value(&station), "or: the slave whose upstream port to close");
    po::variables_map vm;
    const std::string usage = "ecpairctl block-node [--mismatch N | --station S] [--socket PATH]";
    if (auto rc = parse(args, call, extra, {}, vm, usage, out, err)) return *rc;
    if (vm.count("mismatch") != 0 && vm.count("station") != 0) {
        fmt::print(err, "ecpairctl: give --mismatch or --station, not both\nusage: {}\n", usage);
        return kUsage;
    }
    control::Request request;
    auto* b = request.mutable_hc_block_node();
    if (vm.count("mismatch") != 0) b->set_mismatch(mismatch);
    if (vm.count("station") != 0) b->set_station(station);
    auto response = send(call, request, err);
    if (!response) return response.error();
    for (const auto& p : response->hc_ports().ports()) {
        fmt::print(out, "station {} port {} closed: what hangs behind it is cut off\n", p.station(), p.port());
    }
    return kOk;
}

int open_blocked(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Call call;
    po::options_description extra;
    po::variables_map vm;
    if (auto rc = parse(args, call, extra, {}, vm, "ecpairctl open-blocked-ports [--socket PATH]", out, err)) return *rc;
    control::Request request;
    request.mutable_hc_open_blocked_ports();
    auto response = send(call, request, err);
    if (!response) return response.error();
    if (response->hc_ports().ports().empty()) fmt::print(out, "no port was blocked\n");
    for (const auto& p : response->hc_ports().ports()) fmt::print(out, "station {} port {} open again\n", p.station(), p.port());
    return kOk;
}

int port(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Call call;
    std::uint32_t station = 0;
    std::string port_letter;
    std::string setting;
    po::options_description extra;
    extra.add_options()
        ("station", po::value(&station)->required(), "the slave's station address")
        ("port", po::value(&port_letter)->required(), "B, C or D")
        ("setting", po::value(&setting)->required(), "auto, auto-close, open or closed");
    po::positional_options_description positional;
    positional.add("station", 1).add("port", 1).add("setting", 1);
    po::variables_map vm;
    if (auto rc = parse(args, call, extra, positional, vm, "ecpairctl port STATION PORT SETTING [--socket PATH]", out, err)) {
        return *rc;
    }
    control::Request request;
    auto* p = request.mutable_hc_set_port();
    p->set_station(station);
    p->set_port(port_letter);
    p->set_setting(setting);
    auto response = send(call, request, err);
    if (!response) return response.error();
    fmt::print(out, "station {} port {}: {}\n", station, port_letter, setting);
    return kOk;
}

int alias(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Call call;
    std::string verb;
    std::uint32_t station = 0;
    std::string value_text;
    po::options_description extra;
    extra.add_options()
        ("verb", po::value(&verb)->required(), "set")
        ("station", po::value(&station)->required(), "the slave's station address")
        ("value", po::value(&value_text)->required(), "the alias, decimal or 0x hex");
    po::positional_options_description positional;
    positional.add("verb", 1).add("station", 1).add("value", 1);
    po::variables_map vm;
    const std::string usage = "ecpairctl alias set STATION VALUE [--socket PATH]";
    if (auto rc = parse(args, call, extra, positional, vm, usage, out, err)) return *rc;
    if (verb != "set") {
        fmt::print(err, "ecpairctl: alias: '{}' is not 'set'\nusage: {}\n", verb, usage);
        return kUsage;
    }
    std::size_t used = 0;
    unsigned long value = 0;
    try {
        value = std::stoul(value_text, &used, 0);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != value_text.size() || value > 0xFFFF) {
        fmt::print(err, "ecpairctl: alias: VALUE must be 0..65535 (decimal or 0x hex), got '{}'\n", value_text);
        return kUsage;
    }
    control::Request request;
    request.mutable_hc_set_alias()->set_station(station);
    request.mutable_hc_set_alias()->set_alias(static_cast<std::uint32_t>(value));
    auto response = send(call, request, err);
    if (!response) return response.error();
    fmt::print(out, "station {}: SII station alias {} (was {}); the slave takes it over at its next power-on\n", station,
               value, response->hc_alias().previous());
    return kOk;
}

}  // namespace

const char* hot_connect_usage() {
    return "  groups                    Hot-Connect groups, members, presence, mismatches\n"
           "  accept                    accept the topology change waiting (manual modes)\n"
           "  topology-change           run the Hot-Connect state machine now\n"
           "  block-node [--mismatch N | --station S]\n"
           "                            close the port in front of a mismatch or a slave\n"
           "  open-blocked-ports        open what block-node closed\n"
           "  port STATION PORT SETTING set a port auto, auto-close, open or closed\n"
           "  alias set STATION VALUE   program a slave's station alias into its SII\n";
}

std::optional<int> run_hot_connect_command(const std::string& command, const std::vector<std::string>& args,
                                           std::ostream& out, std::ostream& err) {
    if (command == "groups") return groups(args, out, err);
    if (command == "accept") {
        return simple(args, "ecpairctl accept [--socket PATH]", out, err,
                      [](control::Request& r) { r.mutable_hc_accept(); }, "accepted: the new groups go to the master state");
    }
    if (command == "topology-change") {
        return simple(args, "ecpairctl topology-change [--socket PATH]", out, err,
                      [](control::Request& r) { r.mutable_hc_force(); }, "topology change started");
    }
    if (command == "block-node") return block_node(args, out, err);
    if (command == "open-blocked-ports") return open_blocked(args, out, err);
    if (command == "port") return port(args, out, err);
    if (command == "alias") return alias(args, out, err);
    return std::nullopt;
}

}  // namespace ecpair::ctl
