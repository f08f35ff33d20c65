// `ecpairctl watch`: the status (one member, or the pair view with two
// --socket) redrawn every --interval seconds, with the latest events under
// it. Between redraws it sleeps in poll() on the members' event streams: an
// event shows at the next redraw, nothing spins. On a terminal the screen is
// cleared for each redraw; elsewhere the views follow one another, each
// headed by a line with the time.

#include <poll.h>
#include <unistd.h>

#include <deque>
#include <iostream>
#include <optional>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ctl_commands.hpp"
#include "daemon_connection.hpp"
#include "ecpair/control/control_client.hpp"
#include "event_text.hpp"
#include "exit_codes.hpp"
#include "status_command.hpp"
#include "status_sections.hpp"

namespace ecpair::ctl {
namespace {

namespace po = boost::program_options;
using Clock = std::chrono::steady_clock;

struct Watched {
    std::string socket;
    std::optional<control::EventSubscription> events;
    std::string name;  // the member's name once known, for event lines of a pair
};

void draw(std::ostream& out, bool terminal, const std::vector<PairMember>& members,
          const std::deque<std::string>& recent) {
    if (terminal) {
        out << "\x1b[H\x1b[2J";
    } else {
        const auto now = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
        fmt::print(out, "--- {} ---\n", local_time_of(now));
    }
    if (members.size() == 1) {
        if (members[0].status) {
            print_status_table(out, *members[0].status);
        } else {
            fmt::print(out, "{}\n", members[0].error);
        }
    } else {
        print_pair_table(out, members);
    }
    fmt::print(out, "recent events:\n");
    if (recent.empty()) fmt::print(out, "  (none yet)\n");
    for (const auto& line : recent) fmt::print(out, "  {}\n", line);
    out.flush();
}

}  // namespace

int run_watch_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
    SocketOptions sockets;
    double interval = 1.0;
    unsigned count = 0;
    unsigned events_shown = 8;
    po::options_description options("ecpairctl watch options");
    add_socket_options(options, sockets);
    options.add_options()
        ("interval", po::value(&interval), "seconds between redraws (default 1)")
        ("count", po::value(&count), "stop after N redraws (default: until interrupted)")
        ("events", po::value(&events_shown), "how many recent events to show (default 8)");
    po::variables_map vm;
    const std::string usage =
        "ecpairctl watch [--socket PATH [--socket PATH]] [--interval SECONDS] [--count N] [--events N]";
    if (auto rc = parse_arguments(args, options, nullptr, vm, "watch", usage, out, err)) return *rc;
    const auto paths = sockets.paths();
    if (paths.size() > 2 || interval < 0.05) {
        fmt::print(err, "ecpairctl watch: give one or two --socket and an --interval of at least 0.05 s (usage: {})\n",
                   usage);
        return kExitUsage;
    }
    const bool terminal = &out == &std::cout && ::isatty(STDOUT_FILENO) == 1;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval));

    std::vector<Watched> watched;
    for (const auto& path : paths) watched.push_back({path, std::nullopt, path});
    std::deque<std::string> recent;
    int rc = kExitOk;
    for (unsigned drawn = 0; count == 0 || drawn < count; ++drawn) {
        const auto next = Clock::now() + period;
        const auto members = fetch_members(paths);
        rc = kExitOk;
        for (std::size_t i = 0; i < members.size(); ++i) {
            if (members[i].status) watched[i].name = members[i].status->name();
            if (!members[i].status && rc == kExitOk) rc = members[i].exit_code;
            // (Re)subscribe to the events of every member that answers.
            if (members[i].status && !watched[i].events) {
                if (auto opened = control::EventSubscription::open(paths[i])) watched[i].events = std::move(*opened);
            }
        }
        // Events that came since the last redraw (the first time: the daemon's backlog).
        auto collect = [&](Watched& w) {
            if (!w.events) return;
            auto taken = w.events->take();
            if (!taken) {
                w.events.reset();
                return;
            }
            for (const auto& r : *taken) {
                if (!r.has_event()) continue;
                recent.push_back((paths.size() > 1 ? w.name + " " : std::string()) + event_line(r.event()));
                while (recent.size() > events_shown) recent.pop_front();
            }
        };
        for (auto& w : watched) collect(w);
        draw(out, terminal, members, recent);
        if (count != 0 && drawn + 1 == count) break;
        // Sleep until the next redraw, waking for events only to keep them.
        for (auto now = Clock::now(); now < next; now = Clock::now()) {
            std::vector<pollfd> fds;
            for (const auto& w : watched) {
                if (w.events) fds.push_back({w.events->fd(), POLLIN, 0});
            }
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count() + 1;
            if (fds.empty()) {
                ::poll(nullptr, 0, static_cast<int>(left));
                continue;
            }
            if (::poll(fds.data(), fds.size(), static_cast<int>(left)) > 0) {
                for (auto& w : watched) collect(w);
            }
        }
    }
    return rc;
}

}  // namespace ecpair::ctl
