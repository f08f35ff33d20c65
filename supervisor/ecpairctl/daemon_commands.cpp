#include "daemon_commands.hpp"

#include <array>
#include <functional>
#include <map>
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

struct Common {
    std::string socket;
    std::string name = "ecpaird";
    std::string path() const { return socket.empty() ? fmt::format("/run/ecpair/{}.sock", name) : socket; }
};

void add_common(po::options_description& options, Common& common) {
    options.add_options()
        ("help,h", "this text")
        ("socket,s", po::value(&common.socket), "operator socket of the daemon")
        ("name,n", po::value(&common.name), "daemon name: the socket is /run/ecpair/NAME.sock (default ecpaird)");
}

// Parses `args`; nullopt when done (help printed) and an exit code otherwise.
std::optional<int> parse(const std::vector<std::string>& args, po::options_description& options,
                         const po::positional_options_description* positional, po::variables_map& vm,
                         const std::string& usage, std::ostream& out, std::ostream& err) {
    try {
        auto parser = po::command_line_parser(args).options(options);
        if (positional) parser.positional(*positional);
        po::store(parser.run(), vm);
        po::notify(vm);
    } catch (const po::error& e) {
        fmt::print(err, "ecpairctl: {}\nusage: {}\n{}", e.what(), usage, fmt::streamed(options));
        return kUsage;
    }
    if (vm.count("help") != 0) {
        fmt::print(out, "usage: {}\n{}", usage, fmt::streamed(options));
        return kOk;
    }
    return std::nullopt;
}

// Sends one request; the response when the daemon accepted it, else the
// exit code (the error is printed).
Expected<control::Response, int> call_daemon(const std::string& path, const control::Request& request,
                                             std::ostream& err) {
    auto response = control::call(path, request);
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

std::string yes_no(bool b) { return b ? "up" : "DOWN"; }

// The supervisor's view: what this member is and why, its partner, its counters.
void print_supervisor(std::ostream& out, const control::SupervisorStatus& v, const std::string& red_state) {
    fmt::print(out, "  supervisor: {}{} - {}\n", v.state(), v.forced_standby() ? " (FORCED STANDBY)" : "", v.why());
    if (!v.no_active().empty()) fmt::print(out, "  NO MASTER IS ACTIVE: {}\n", v.no_active());
    if (red_state == "ACTIVE") {
        fmt::print(out, "  partner {}: {}{}\n", v.partner().empty() ? "-" : v.partner(),
                   v.partner_standby().empty() ? "no answer" : v.partner_standby() + " standby",
                   v.partner_answer_age_ms() >= 0 ? fmt::format(", last answer {:.1f} ms ago", v.partner_answer_age_ms())
                                                  : std::string());
    } else {
        fmt::print(out, "  partner {}: last CMF {}, silence {:.1f} of {} ms (comm timeout)\n",
                   v.partner().empty() ? "-" : v.partner(),
                   v.last_cmf_age_ms() >= 0 ? fmt::format("{:.1f} ms ago", v.last_cmf_age_ms()) : std::string("never"),
                   v.silence_ms(), v.comm_timeout_ms());
    }
    if (v.handoff_cycle() != 0) fmt::print(out, "  hand-off at cycle {}\n", v.handoff_cycle());
    fmt::print(out, "  epoch {}, arbitration {}; takeovers {}, comm timeouts {}, collisions {} (backoffs won {}, lost {}), "
                    "hand-offs {} ({} cancelled), partner lost {}\n",
               v.epoch(), v.arbitration(), v.takeovers(), v.comm_timeouts(), v.collisions(), v.backoffs_won(),
               v.backoffs_lost(), v.handoffs(), v.handoffs_cancelled(), v.partner_lost());
}

void print_status(std::ostream& out, const control::StatusReply& s) {
    fmt::print(out, "{}: master {} (target {}), cycle {} µs\n", s.name(), s.master_state(), s.target_state(),
               s.cycle_time_us());
    if (!s.sequence_error().empty()) fmt::print(out, "  state machine stopped: {}\n", s.sequence_error());
    fmt::print(out, "  links: MAIN {}, RED {}; ring {}{}\n", yes_no(s.main_link_up()), yes_no(s.red_link_up()),
               s.ring_state(),
               s.ring_state() == "broken" && s.reachable_from_main() > 0
                   ? fmt::format(" after slave {}", s.reachable_from_main())
                   : std::string());
    const auto& t = s.timing();
    fmt::print(out, "  cycles {} ({} late, {} skipped; wake-up latency p50 {:.0f} µs, p99 {:.0f} µs, max {:.0f} µs{})\n",
               t.cycles(), t.late(), t.skipped(), t.wake_latency_p50_us(), t.wake_latency_p99_us(),
               t.wake_latency_max_us(), t.realtime() ? ", SCHED_FIFO" : "");
    const auto& c = s.counters();
    fmt::print(out, "  frames sent {}, lost {}, late copies {}, incomplete cycles {}, WKC errors {}, foreign {}\n",
               c.frames_sent(), c.frames_lost(), c.late_copies(), c.cycles_incomplete(), c.wkc_errors(),
               c.foreign_frames());
    if (s.redundancy().enabled()) {
        const auto& r = s.redundancy();
        fmt::print(out, "  redundancy: {}, partner {}{}\n", r.red_state(), r.partner_seen() ? "seen" : "NOT seen",
                   r.red_state() == "INACTIVE" ? fmt::format(", mirrored cycle {}", r.mirrored_cycle()) : std::string());
        if (!r.partner_mismatch().empty()) fmt::print(out, "  partner differs (cold standby): {}\n", r.partner_mismatch());
        if (s.has_supervisor()) print_supervisor(out, s.supervisor(), r.red_state());
        auto hex = [](const std::string& bytes) {
            std::string text;
            for (const char byte : bytes.substr(0, 16)) text += fmt::format("{:02x}", static_cast<unsigned char>(byte));
            return text.empty() ? std::string("-") : text;
        };
        fmt::print(out, "  master PD out {} in {}\n", hex(r.master_pd_out()), hex(r.master_pd_in()));
        if (r.red_state() == "INACTIVE") {
            fmt::print(out, "  store-and-forward: {} to MAIN, {} to RED, {} bounced, dropped: {} circulating, {} non-EtherCAT, {} damaged\n",
                       r.forwarded_main(), r.forwarded_red(), r.bounced(), r.dropped_circulating(),
                       r.dropped_non_ethercat(), r.dropped_damaged());
        }
    }
    if (s.loopback().cycles_checked() > 0) {
        fmt::print(out, "  loopback check: {} cycles, {} slave checks, {} mismatches\n", s.loopback().cycles_checked(),
                   s.loopback().slave_checks(), s.loopback().mismatches());
    }
    fmt::print(out, "  {:>3}  {:<7}  {:<8}  {:<11}  {}\n", "POS", "STATION", "PRESENT", "STATE", "NAME");
    for (const auto& slave : s.slaves()) {
        fmt::print(out, "  {:>3}  {:<7}  {:<8}  {:<11}  {}{}\n", slave.position(), slave.station_address(),
                   slave.present() ? "yes" : "no", slave.al_state(), slave.name(),
                   slave.al_status_code() != 0 ? fmt::format(" (AL status code 0x{:04x})", slave.al_status_code())
                                               : std::string());
    }
    auto variables = [&out](const char* title, const auto& list) {
        if (list.empty()) return;
        fmt::print(out, "  {}:\n", title);
        for (const auto& v : list) fmt::print(out, "    {:<48} 0x{:0{}x}\n", v.name(), v.value(), (v.bit_size() + 3) / 4);
    };
    variables("inputs", s.inputs());
    variables("outputs", s.outputs());
}

}  // namespace

int run_status_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Common common;
    std::uint32_t variables = 0;
    po::options_description options("ecpairctl status options");
    add_common(options, common);
    options.add_options()("variables", po::value(&variables), "show the first N input and output variables");
    po::variables_map vm;
    if (auto rc = parse(args, options, nullptr, vm, "ecpairctl status [--socket PATH] [--variables N]", out, err)) return *rc;

    control::Request request;
    request.mutable_status()->set_max_variables(variables);
    auto response = call_daemon(common.path(), request, err);
    if (!response) return response.error();
    print_status(out, response->status());
    return kOk;
}

int run_events_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Common common;
    double seconds = 0;
    po::options_description options("ecpairctl events options");
    add_common(options, common);
    options.add_options()("for", po::value(&seconds), "stop after SECONDS (default: until interrupted)");
    po::variables_map vm;
    if (auto rc = parse(args, options, nullptr, vm, "ecpairctl events [--socket PATH] [--for SECONDS]", out, err)) return *rc;

    control::Request request;
    request.mutable_watch_events();
    bool refused = false;
    auto streamed = control::stream(
        common.path(), request,
        [&](const control::Response& r) {
            if (!r.ok()) {
                fmt::print(err, "ecpairctl: {}\n", r.error());
                refused = true;
                return false;
            }
            if (r.has_event()) {
                fmt::print(out, "{} {}\n", r.event().kind(), r.event().text());
                out.flush();
            }
            return true;
        },
        std::chrono::milliseconds(static_cast<std::int64_t>(seconds * 1000)));
    if (!streamed) {
        fmt::print(err, "ecpairctl: {}\n", streamed.error().message);
        return kUnreachable;
    }
    return refused ? kRefused : kOk;
}

namespace {

// The state commands differ only in the request they send.
int run_state_request(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, const char* usage,
                      const char* values, const std::function<void(control::Request&, const std::string&)>& fill) {
    Common common;
    std::string state;
    po::options_description options("ecpairctl options");
    add_common(options, common);
    options.add_options()("state", po::value(&state)->required(), values);
    po::positional_options_description positional;
    positional.add("state", 1);
    po::variables_map vm;
    if (auto rc = parse(args, options, &positional, vm, usage, out, err)) return *rc;

    control::Request request;
    fill(request, state);
    if (auto response = call_daemon(common.path(), request, err); !response) return response.error();
    fmt::print(out, "{} requested\n", state);
    return kOk;
}

}  // namespace

int run_compare_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    std::vector<std::string> sockets;
    po::options_description options("ecpairctl compare options");
    options.add_options()("help,h", "this text")("socket,s", po::value(&sockets)->composing(),
                                                 "operator socket of a pair member (give two)");
    po::variables_map vm;
    if (auto rc = parse(args, options, nullptr, vm, "ecpairctl compare --socket A --socket B", out, err)) return *rc;
    if (sockets.size() != 2) {
        fmt::print(err, "ecpairctl compare: give exactly two --socket\n");
        return kUsage;
    }
    std::array<std::map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>>, 2> histories;
    for (std::size_t i = 0; i < 2; ++i) {
        control::Request request;
        request.mutable_image_history();
        auto response = call_daemon(sockets[i], request, err);
        if (!response) return response.error();
        // Only SAFEOP and OP carry outputs on the wire: before, nothing can be mirrored.
        for (const auto& e : response->image_history().entries()) {
            if (e.master_state() == "SAFEOP" || e.master_state() == "OP") {
                histories[i][e.cycle()] = {e.inputs_crc(), e.outputs_crc()};
            }
        }
    }
    std::size_t common = 0;
    std::size_t differ = 0;
    for (const auto& [cycle, crcs] : histories[0]) {
        const auto it = histories[1].find(cycle);
        if (it == histories[1].end()) continue;
        ++common;
        if (it->second != crcs) ++differ;
    }
    fmt::print(out, "{} cycles recorded by both: {} with equal inputs and outputs, {} differ\n", common, common - differ,
               differ);
    return common > 0 && differ == 0 ? kOk : kRefused;
}

int run_state_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    return run_state_request(args, out, err, "ecpairctl state [--socket PATH] STATE", "INIT, PREOP, SAFEOP or OP",
                             [](control::Request& r, const std::string& s) { r.mutable_set_master_state()->set_state(s); });
}

int run_red_state_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    return run_state_request(args, out, err, "ecpairctl red-state [--socket PATH] ACTIVE|INACTIVE", "ACTIVE or INACTIVE",
                             [](control::Request& r, const std::string& s) { r.mutable_set_red_state()->set_state(s); });
}

int run_pair_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, PairCommand command) {
    static constexpr const char* kUsage[] = {"ecpairctl switchover [--socket PATH]",
                                             "ecpairctl force-standby [--socket PATH]",
                                             "ecpairctl unforce-standby [--socket PATH]"};
    const auto which = static_cast<std::size_t>(command);
    Common common;
    po::options_description options("ecpairctl options");
    add_common(options, common);
    po::variables_map vm;
    if (auto rc = parse(args, options, nullptr, vm, kUsage[which], out, err)) return *rc;
    control::Request request;
    switch (command) {
        case PairCommand::Switchover: request.mutable_switchover(); break;
        case PairCommand::ForceStandby: request.mutable_force_standby()->set_forced(true); break;
        case PairCommand::UnforceStandby: request.mutable_force_standby()->set_forced(false); break;
    }
    if (auto response = call_daemon(common.path(), request, err); !response) return response.error();
    static constexpr const char* kDone[] = {
        "switchover started: watch the events for the hand-off (or `ecpairctl status`)",
        "forced to standby: this member will not become ACTIVE (an ACTIVE one hands over first)",
        "standby no longer forced"};
    fmt::print(out, "{}\n", kDone[which]);
    return kOk;
}

}  // namespace ecpair::ctl
