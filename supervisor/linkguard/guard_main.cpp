// ecpair-linkguard: takes a failed ecpaird's MAIN and RED links down
// (acontis REQ012), so that the slaves and the partner close their ports and
// the survivor's frames come back.
//
//   ecpair-linkguard --fd N --name NAME --main IF [--red IF] --hang-timeout-ms MS
//                    [--realtime-priority P] [--log-level L]
//       started by ecpaird, which holds the other end of socket N: guards
//       until ecpaird is gone or stops (then the links go down) and takes the
//       links down when the heartbeat stops for MS (they stay down until
//       ecpaird asks for them).
//   ecpair-linkguard --config FILE --down
//       once: the links of that configuration down (systemd's ExecStopPost,
//       the second line of defence); nothing when its link guard is off.
//
// SIGINT, SIGTERM and SIGHUP are ignored: the guard's life is tied to the
// socket, not to signals meant for ecpaird (a Ctrl-C, systemctl stop).

#include <signal.h>
#include <unistd.h>

#include <iostream>

#include <boost/program_options.hpp>

#include "ecpair/common/log.hpp"
#include "ecpair/common/realtime.hpp"
#include "ecpair/config/daemon_settings.hpp"
#include "ecpair/systemd/journal.hpp"
#include "guard_runner.hpp"

namespace {

namespace po = boost::program_options;
using namespace ecpair::linkguard;

constexpr int kOk = 0;
constexpr int kFailed = 1;
constexpr int kUsage = 2;

int links_down_once(const std::string& config_path) {
    auto settings = ecpair::config::load_daemon_settings(config_path);
    if (!settings) {
        std::cerr << "ecpair-linkguard: " << settings.error().describe() << "\n";
        return kUsage;
    }
    const GuardInterfaces interfaces{settings->main_interface, settings->red_interface};
    if (!settings->link_guard.enabled) {
        ecpair::logger("linkguard")->info("link guard {}: off in {}; {} left alone", settings->name, config_path,
                                          interfaces.describe());
        return kOk;
    }
    auto admin = ecpair::link::LinkAdmin::open();
    if (!admin) {
        std::cerr << "ecpair-linkguard: " << admin.error().message << "\n";
        return kFailed;
    }
    const auto result = set_links(**admin, interfaces, false);
    if (result.error != 0) {
        ecpair::logger("linkguard")->error("link guard {}: taking {} down failed: {}", settings->name,
                                           interfaces.describe(), result.message);
        return kFailed;
    }
    ecpair::logger("linkguard")->warn("link guard {}: {} down (ecpaird stopped)", settings->name, interfaces.describe());
    return kOk;
}

}  // namespace

int main(int argc, char** argv) {
    int fd = -1;
    std::string name = "ecpaird";
    std::string config;
    GuardInterfaces interfaces;
    unsigned hang_timeout_ms = 0;
    int priority = 0;
    std::string log_level = "info";
    po::options_description options("ecpair-linkguard options");
    options.add_options()
        ("help,h", "this text")
        ("fd", po::value(&fd), "socket shared with ecpaird (started by ecpaird)")
        ("name", po::value(&name), "the ecpaird instance, for log lines")
        ("main", po::value(&interfaces.main), "MAIN interface")
        ("red", po::value(&interfaces.red), "RED interface")
        ("hang-timeout-ms", po::value(&hang_timeout_ms), "links down after this long without a heartbeat")
        ("realtime-priority", po::value(&priority), "SCHED_FIFO priority (0: none)")
        ("log-level", po::value(&log_level), "trace, debug, info, warn, error")
        ("config", po::value(&config), "an ecpaird configuration (with --down)")
        ("down", "set the configuration's links down once and exit");
    po::variables_map vm;
    try {
        po::store(po::parse_command_line(argc, argv, options), vm);
        po::notify(vm);
    } catch (const po::error& e) {
        std::cerr << "ecpair-linkguard: " << e.what() << " (see --help)\n";
        return kUsage;
    }
    if (vm.count("help") != 0) {
        std::cout << "usage: ecpair-linkguard --fd N --main IF [--red IF] --hang-timeout-ms MS ...\n"
                     "       ecpair-linkguard --config FILE --down\n"
                  << options;
        return kOk;
    }
    ecpair::systemd::log_to_journal_if_connected("ecpair-linkguard");
    if (!ecpair::set_log_level(log_level)) {
        std::cerr << "ecpair-linkguard: --log-level: '" << log_level << "' is not a level\n";
        return kUsage;
    }
    if (vm.count("down") != 0) {
        if (config.empty()) {
            std::cerr << "ecpair-linkguard: --down needs --config FILE\n";
            return kUsage;
        }
        return links_down_once(config);
    }
    if (fd < 0 || interfaces.main.empty() || hang_timeout_ms == 0) {
        std::cerr << "ecpair-linkguard: --fd, --main and --hang-timeout-ms are required (ecpaird starts the guard)\n";
        return kUsage;
    }
    for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ::signal(signal, SIG_IGN);
    ecpair::request_realtime(priority, "link guard");

    auto admin = ecpair::link::LinkAdmin::open();
    if (!admin) {
        std::cerr << "ecpair-linkguard: " << admin.error().message << "\n";
        return kFailed;
    }
    GuardOptions guard;
    guard.name = name;
    guard.links = interfaces.describe();
    guard.hang_timeout = std::chrono::milliseconds(hang_timeout_ms);
    ecpair::logger("linkguard")->info("link guard {}: guarding {} (down after {} ms without a heartbeat, or when ecpaird ends)",
                                      name, guard.links, hang_timeout_ms);
    GuardRunner runner(fd, interfaces, guard, std::move(*admin));
    return runner.run();
}
