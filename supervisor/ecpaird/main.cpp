// ecpaird: one controller of an ecpair pair (for now a single master): loads
// its configuration and ENI, drives the slaves to the target state and keeps
// them there until SIGINT/SIGTERM.

#include <iostream>

#include <boost/program_options.hpp>

#include "daemon.hpp"
#include "open_file_limit.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/systemd/journal.hpp"

int main(int argc, char** argv) {
    namespace po = boost::program_options;
    std::string config_path;
    std::string log_level;
    po::options_description options("ecpaird options");
    options.add_options()
        ("help,h", "this text")
        ("config,c", po::value(&config_path), "configuration file (.textproto), required")
        ("check", "validate the configuration and the ENI, then exit")
        ("log-level", po::value(&log_level), "override the configuration's log level");
    ecpair::systemd::log_to_journal_if_connected("ecpaird");
    po::variables_map vm;
    try {
        po::store(po::parse_command_line(argc, argv, options), vm);
        po::notify(vm);
    } catch (const po::error& e) {
        std::cerr << "ecpaird: " << e.what() << "\n" << options;
        return ecpair::daemon::Daemon::kBadConfig;
    }
    if (vm.count("help") != 0) {
        std::cout << "usage: ecpaird --config FILE [--check] [--log-level L]\n" << options;
        return 0;
    }
    if (config_path.empty()) {
        std::cerr << "ecpaird: --config is required\n" << options;
        return ecpair::daemon::Daemon::kBadConfig;
    }
    auto settings = ecpair::config::load_daemon_settings(config_path);
    if (!settings) {
        std::cerr << "ecpaird: " << settings.error().describe() << "\n";
        return ecpair::daemon::Daemon::kBadConfig;
    }
    if (!log_level.empty()) settings->log_level = log_level;
    if (!ecpair::set_log_level(settings->log_level)) {
        std::cerr << "ecpaird: --log-level: '" << settings->log_level << "' is not a level\n";
        return ecpair::daemon::Daemon::kBadConfig;
    }
    if (vm.count("check") != 0) {
        auto eni = ecpair::eni::load_eni_file(settings->eni_path);
        if (!eni) {
            std::cerr << "ecpaird: " << eni.error().describe() << "\n";
            return ecpair::daemon::Daemon::kBadConfig;
        }
        std::cout << config_path << ": valid; ENI " << settings->eni_path << " with " << (*eni)->slaves.size()
                  << " slave(s)\n";
        return 0;
    }
    // Operator clients, links, the link guard's socket at the top (LinkGuard).
    ecpair::daemon::raise_open_file_limit(65536);
    ecpair::daemon::Daemon daemon(std::move(*settings));
    if (const int rc = daemon.open(); rc != 0) return rc;
    return daemon.run();
}
