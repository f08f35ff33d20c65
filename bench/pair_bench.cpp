// ecpair-pair-bench: how the pair behaves when it matters, measured on the
// wire of a simulated segment (network namespaces, veth cables, ecsim with
// its capture), with two real ecpaird started with no role.
//
//   failover       [--runs 30]  kill -9 the ACTIVE (its link guard takes its
//                               links down), until the standby has taken
//                               over; the gap in process data at the slaves,
//                               the time until the new ACTIVE's background
//                               scan confirms the topology; the killed member
//                               is restarted (it comes back INACTIVE)
//   switchover     [--runs 50]  `ecpairctl switchover` on the ACTIVE: gap at
//                               the slaves, cycles no master sent, cycles two
//                               masters sent
//   false-failover [--seconds 600] [--hog]  the pair left alone (with a busy
//                               process on every core): takeovers, the
//                               longest silence the standby counted
//
// Common: --slaves N (33) --cycle-us US (1000) --comm-timeout-ms MS (config
// default) --keep (leave the files in /tmp). Prints its figures; needs root.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <thread>
#include <vector>

#include <boost/program_options.hpp>

#include "ecpair/sim/eni_generator.hpp"
#include "supervised_pair.hpp"

namespace po = boost::program_options;
using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

struct Options {
    std::string mode;
    int runs = 0;
    int seconds = 600;
    bool hog = false;
    std::uint32_t slaves = 33;
    std::uint32_t cycle_us = 1000;
    std::uint32_t comm_timeout_ms = 0;
};

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1))];
}

void print_stats(const char* what, const std::vector<double>& ms, double cycle_ms) {
    if (ms.empty()) {
        std::printf("%s: no samples\n", what);
        return;
    }
    const double mn = *std::min_element(ms.begin(), ms.end());
    const double mx = *std::max_element(ms.begin(), ms.end());
    std::printf("%s (%zu runs): min %.2f ms, p50 %.2f ms, p99 %.2f ms, max %.2f ms", what, ms.size(), mn,
                percentile(ms, 50), percentile(ms, 99), mx);
    if (cycle_ms > 0) {
        std::printf("  = %.1f / %.1f / %.1f / %.1f cycles", mn / cycle_ms, percentile(ms, 50) / cycle_ms,
                    percentile(ms, 99) / cycle_ms, mx / cycle_ms);
    }
    std::printf("\n");
}

// A generated segment of options.slaves slaves (8 bytes in and out each).
std::filesystem::path generated_eni(const Options& o, const std::filesystem::path& dir) {
    ecpair::sim::GeneratedEniOptions eni;
    eni.slaves = o.slaves;
    eni.input_bytes = 8;
    eni.output_bytes = 8;
    eni.cycle_time_us = o.cycle_us;
    const auto path = dir / "bench.xml";
    std::ofstream(path) << ecpair::sim::generate_eni(eni);
    return path;
}

PairSetup setup_of(const Options& o, const std::filesystem::path& eni) {
    PairSetup setup;
    setup.eni = eni;
    setup.cycle_us = o.cycle_us;
    setup.demo = "WALKING_BIT";
    setup.log_level = "info";
    if (o.comm_timeout_ms > 0) setup.redundancy = "comm_timeout_ms: " + std::to_string(o.comm_timeout_ms);
    setup.extra_config = "link_guard { enabled: true }";
    return setup;
}

class Bench {
public:
    explicit Bench(const Options& o) : options_(o), pair_(setup_of(o, generated_eni(o, files_.path())), "ecpair-pair-bench") {}

    EcpairdProcess& member(int i) { return pair_.member(i); }
    int settle() { return pair_.settled(); }

    int failover() {
        std::vector<double> verified_ms;
        for (int run = 0; run < options_.runs; ++run) {
            const int active = settle();
            const int standby = 1 - active;
            EventRecorder events(member(standby).socket());
            std::this_thread::sleep_for(300ms);
            const auto killed_at = std::chrono::system_clock::now();
            pair_.kill(active);  // its link guard takes its links down
            const auto verified = events.wait_for("topology-verified", "confirms", 10s);
            if (verified) {
                const auto at = std::chrono::system_clock::time_point(std::chrono::milliseconds(verified->unix_time_ms()));
                verified_ms.push_back(std::chrono::duration<double, std::milli>(at - killed_at).count());
            }
            if (!member(standby).wait_for([](const StatusReply& s) { return is_active(s) && all_slaves_op(s); }, 10s)) {
                std::fprintf(stderr, "run %d: no takeover\n", run);
                return 1;
            }
            pair_.restart(active);  // comes back INACTIVE; its links come up when it starts
        }
        settle();
        const auto capture = finish();
        std::vector<double> gaps;
        for (const auto& h : capture.handovers()) gaps.push_back(h.gap_us / 1000.0);
        std::printf("failover after kill -9, %u slaves, %u µs cycle, link guard on\n", options_.slaves,
                    options_.cycle_us);
        print_stats("  gap in process data at the slaves", gaps, cycle_ms());
        print_stats("  kill -9 to the new ACTIVE's verified topology", verified_ms, 0);
        return gaps.size() == static_cast<std::size_t>(options_.runs) ? 0 : 1;
    }

    int switchover() {
        const auto from = pair_.settled_cycle();  // after a start-up collision, if any
        for (int run = 0; run < options_.runs; ++run) {
            const int active = settle();
            const auto refused = member(active).switchover();
            if (!refused.empty()) {
                std::fprintf(stderr, "run %d: %s\n", run, refused.c_str());
                return 1;
            }
            if (!member(1 - active).wait_for(is_active, 5s)) return 1;
        }
        settle();
        const auto capture = finish();
        std::vector<double> gaps;
        for (const auto& h : capture.handovers()) gaps.push_back(h.gap_us / 1000.0);
        std::printf("switchover (zero-loss hand-off), %u slaves, %u µs cycle\n", options_.slaves, options_.cycle_us);
        print_stats("  gap in process data at the slaves", gaps, cycle_ms());
        std::printf("  cycles no master numbered: %zu; cycles two masters numbered: %zu\n",
                    capture.missing_cycles(from).size(), capture.doubled_cycles(from).size());
        std::printf("  longest gap in process data over the whole run: %.2f ms\n", capture.longest_gap_us() / 1000.0);
        return 0;
    }

    int false_failover() {
        const int active = settle();
        const int standby = 1 - active;
        const auto before = member(standby).status().supervisor();
        std::vector<pid_t> hogs;
        if (options_.hog) {
            const auto cores = std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN));
            for (long i = 0; i < cores; ++i) {
                const pid_t pid = ::fork();
                if (pid == 0) {
                    std::atomic<std::uint64_t> spin{0};  // a load the optimiser cannot remove
                    for (;;) spin.fetch_add(1, std::memory_order_relaxed);
                }
                hogs.push_back(pid);
            }
        }
        std::this_thread::sleep_for(std::chrono::seconds(options_.seconds));
        for (const pid_t pid : hogs) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, nullptr, 0);
        }
        const auto a = member(active).status();
        const auto b = member(standby).status();
        std::printf("false failovers: %u slaves, %u µs cycle, %d s%s\n", options_.slaves, options_.cycle_us,
                    options_.seconds, options_.hog ? ", a busy process on every core" : "");
        std::printf("  takeovers: %llu, comm timeouts: %llu, collisions: %llu\n",
                    static_cast<unsigned long long>(b.supervisor().takeovers() - before.takeovers()),
                    static_cast<unsigned long long>(b.supervisor().comm_timeouts() - before.comm_timeouts()),
                    static_cast<unsigned long long>(a.supervisor().collisions() + b.supervisor().collisions()));
        std::printf("  longest silence the standby counted: %.2f ms (comm timeout %u ms)\n",
                    b.supervisor().longest_silence_ms(), b.supervisor().comm_timeout_ms());
        std::printf("  ACTIVE: %llu cycles, %llu late, wake-up latency p99 %.0f µs, max %.0f µs\n",
                    static_cast<unsigned long long>(a.timing().cycles()), static_cast<unsigned long long>(a.timing().late()),
                    a.timing().wake_latency_p99_us(), a.timing().wake_latency_max_us());
        std::printf("  standby: wake-up latency p99 %.0f µs, max %.0f µs\n", b.timing().wake_latency_p99_us(),
                    b.timing().wake_latency_max_us());
        finish();
        return is_active(a) && !is_active(b) ? 0 : 1;
    }

private:
    double cycle_ms() const { return static_cast<double>(options_.cycle_us) / 1000.0; }
    SegmentCapture finish() { return pair_.capture(); }

    Options options_;
    TempDir files_{"ecpair-pair-bench-eni"};
    SupervisedPair pair_;
};

}  // namespace

int main(int argc, char** argv) {
    Options o;
    po::options_description options("ecpair-pair-bench MODE [options]");
    options.add_options()("help,h", "this text")("mode", po::value(&o.mode), "failover, switchover or false-failover")(
        "runs", po::value(&o.runs), "runs (failover 30, switchover 50)")(
        "seconds", po::value(&o.seconds), "false-failover: how long (600)")("hog", "false-failover: a busy process per core")(
        "slaves", po::value(&o.slaves), "generated slaves (33)")("cycle-us", po::value(&o.cycle_us), "cycle time (1000)")(
        "comm-timeout-ms", po::value(&o.comm_timeout_ms), "the pair's comm timeout (default: the config's)");
    po::positional_options_description positional;
    positional.add("mode", 1);
    po::variables_map vm;
    try {
        po::store(po::command_line_parser(argc, argv).options(options).positional(positional).run(), vm);
        po::notify(vm);
    } catch (const po::error& e) {
        std::cerr << "ecpair-pair-bench: " << e.what() << "\n" << options;
        return 2;
    }
    if (vm.count("help") != 0 || o.mode.empty()) {
        std::cout << options;
        return o.mode.empty() ? 2 : 0;
    }
    o.hog = vm.count("hog") != 0;
    if (o.runs == 0) o.runs = o.mode == "failover" ? 30 : 50;
    try {
        Bench bench(o);
        if (o.mode == "failover") return bench.failover();
        if (o.mode == "switchover") return bench.switchover();
        if (o.mode == "false-failover") return bench.false_failover();
    } catch (const std::exception& e) {
        std::cerr << "ecpair-pair-bench: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "ecpair-pair-bench: unknown mode '" << o.mode << "'\n";
    return 2;
}
