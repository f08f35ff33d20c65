// The link guard on veth, in network namespaces (a single ecpaird with
// cable redundancy, 5 slaves in ecsim, 1 ms, hang_timeout 50 ms):
//   1. kill -9 of ecpaird until both slave-side cable ends have lost carrier,
//      as the kernel reports it (netlink), RUNS times;
//   2. SIGSTOP until the same, and SIGCONT until the links are up again,
//      HANGS times;
//   3. the longest time between two heartbeats over SECONDS, with a CPU hog
//      (a busy loop at normal priority) on every core: how much of the
//      hang_timeout the heartbeat thread's wake-ups use.
//
//   sudo build/bench/ecpair-link-guard-bench [RUNS] [HANGS] [SECONDS]   (defaults: 30 10 60)

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <iostream>
#include <thread>

#include <fmt/format.h>

#include "bench_args.hpp"
#include "bench_stats.hpp"
#include "ecpair/link/link_admin.hpp"
#include "ecpair/link/link_state_monitor.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

const std::filesystem::path kEni = std::string(ECPAIR_SOURCE_DIR "/tests/data/eni/twincat_kpierczy_5slaves.xml");

EcpairdSettings guarded(const TempDir& dir) {
    EcpairdSettings s;
    s.eni = kEni;
    s.dir = dir.path();
    s.demo = "WALKING_BIT";
    s.extra_config = "cycle_time_us: 1000\nlink_guard { enabled: true hang_timeout_ms: 50 }\n";
    return s;
}

std::unique_ptr<ecpair::link::LinkStateMonitor> far_ends(const RingTopology& topology) {
    NamespaceScope inside(topology.sim());
    auto opened = ecpair::link::LinkStateMonitor::open({"sim-main", "sim-red"});
    if (!opened) throw std::runtime_error(opened.error().message);
    return std::move(*opened);
}

// Waits until the monitor reports both ends in `up`; the time since `from` in ms.
double until_both(ecpair::link::LinkStateMonitor& monitor, bool up, Clock::time_point from) {
    const auto give_up = Clock::now() + 10s;
    while (Clock::now() < give_up) {
        if (monitor.is_up("sim-main") == up && monitor.is_up("sim-red") == up) {
            return std::chrono::duration<double, std::milli>(Clock::now() - from).count();
        }
        pollfd entry{monitor.selectable_fd(), POLLIN, 0};
        ::poll(&entry, 1, 100);
        (void)monitor.read_changes();
    }
    throw std::runtime_error("the cable ends did not change within 10 s");
}

void wait_running(EcpairdProcess& m1) {
    if (!m1.wait_for([](const ecpair::control::StatusReply& s) { return s.timing().cycles() > 300; }, 20s)) {
        throw std::runtime_error("ecpaird did not run:\n" + m1.log());
    }
}

}  // namespace

int main(int argc, char** argv) {
    constexpr const char* kUsage = "ecpair-link-guard-bench [RUNS] [HANGS] [SECONDS]   (defaults: 30 10 60)";
    const int runs = ecpair::bench::positional_count(argc, argv, 1, 30, kUsage);
    const int hangs = ecpair::bench::positional_count(argc, argv, 2, 10, kUsage);
    const int seconds = ecpair::bench::positional_count(argc, argv, 3, 60, kUsage);
    TempDir dir{"ecpair-guard-bench"};
    RingTopology topology(Controllers::Single);
    EcsimProcess ecsim(topology.sim(), {kEni, "sim-main", std::string("sim-red"), dir.path(), 70});

    std::vector<double> after_kill;
    for (int run = 0; run < runs; ++run) {
        EcpairdProcess m1(topology.m1(), guarded(dir));
        wait_running(m1);
        auto monitor = far_ends(topology);
        until_both(*monitor, true, Clock::now());
        const auto killed = Clock::now();
        ::kill(m1.pid(), SIGKILL);
        after_kill.push_back(until_both(*monitor, false, killed));
        m1.wait_for_exit(10s);
        std::filesystem::remove(m1.socket());  // left behind by the killed daemon
    }
    fmt::print("kill -9 -> both slave-side ends without carrier: {}\n", ecpair::bench::spread(after_kill, "ms"));

    std::vector<double> after_stop;
    std::vector<double> after_cont;
    {
        EcpairdProcess m1(topology.m1(), guarded(dir));
        wait_running(m1);
        auto monitor = far_ends(topology);
        for (int run = 0; run < hangs; ++run) {
            until_both(*monitor, true, Clock::now());
            std::this_thread::sleep_for(300ms);
            const auto stopped = Clock::now();
            ::kill(m1.pid(), SIGSTOP);
            after_stop.push_back(until_both(*monitor, false, stopped));
            const auto continued = Clock::now();
            ::kill(m1.pid(), SIGCONT);
            after_cont.push_back(until_both(*monitor, true, continued));
        }
    }
    fmt::print("SIGSTOP -> both ends without carrier (hang_timeout 50 ms): {}\n", ecpair::bench::spread(after_stop, "ms"));
    fmt::print("SIGCONT -> both ends with carrier again: {}\n", ecpair::bench::spread(after_cont, "ms"));

    std::vector<pid_t> hogs;
    for (unsigned core = 0; core < std::max(1u, std::thread::hardware_concurrency()); ++core) {
        const pid_t hog = ::fork();
        if (hog == 0) {
            std::atomic<std::uint64_t> spin{0};
            for (;;) spin.fetch_add(1, std::memory_order_relaxed);
        }
        hogs.push_back(hog);
    }
    {
        EcpairdProcess m1(topology.m1(), guarded(dir));
        wait_running(m1);
        std::this_thread::sleep_for(std::chrono::seconds(seconds));
        const auto s = m1.status();
        fmt::print("{} s with a CPU hog on each of {} cores: longest heartbeat gap {:.1f} ms (heartbeat every 12.5 ms, "
                   "hang_timeout 50 ms); links taken down {} times; {} late cycles of {}\n",
                   seconds, hogs.size(), s.link_guard().max_heartbeat_gap_ms(), s.link_guard().links_taken_down(),
                   s.timing().late(), s.timing().cycles());
    }
    for (const pid_t hog : hogs) {
        ::kill(hog, SIGKILL);
        ::waitpid(hog, nullptr, 0);
    }
    return 0;
}
