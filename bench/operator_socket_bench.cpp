// Late cycles of one ecpaird (33 slaves, ~5 kB of process data, 1 ms, cable
// redundancy, in network namespaces) for SECONDS without operator clients,
// then for SECONDS with CLIENTS idle connections on its operator socket, and
// for SECONDS with CLIENTS watchers receiving every event.
//
//   sudo build/bench/ecpair-operator-socket-bench [SECONDS] [CLIENTS]   (defaults: 60 1000)

#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <thread>

#include <fmt/format.h>

#include "ecpair/control/delimited.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

int connect_to(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        throw std::runtime_error(fmt::format("connect {}: {}", path, std::strerror(errno)));
    }
    return fd;
}

struct Window {
    std::uint64_t cycles;
    std::uint64_t late;
    double p99_us;
};

Window measure(const EcpairdProcess& m1, int seconds) {
    const auto start = m1.status();
    std::this_thread::sleep_for(std::chrono::seconds(seconds));
    const auto end = m1.status();
    return {end.timing().cycles() - start.timing().cycles(), end.timing().late() - start.timing().late(),
            end.timing().wake_latency_p99_us()};
}

}  // namespace

int main(int argc, char** argv) {
    const int seconds = argc > 1 ? std::stoi(argv[1]) : 60;
    const int clients = argc > 2 ? std::stoi(argv[2]) : 1000;
    rlimit limit{};
    ::getrlimit(RLIMIT_NOFILE, &limit);
    limit.rlim_cur = std::min<rlim_t>(limit.rlim_max, static_cast<rlim_t>(clients) + 1024);
    ::setrlimit(RLIMIT_NOFILE, &limit);

    TempDir dir{"ecpair-socket-bench"};
    const auto eni = dir / "bench.xml";
    std::ofstream(eni) << ecpair::sim::generate_eni({});
    RingTopology topology(Controllers::Single);
    EcsimProcess ecsim(topology.sim(), {eni, "sim-main", std::string("sim-red"), dir.path(), 70});
    EcpairdSettings settings;
    settings.eni = eni;
    settings.dir = dir.path();
    settings.demo = "LOOPBACK_CHECK";
    settings.extra_config = "cycle_time_us: 1000\n";
    settings.control_extra = fmt::format("request_timeout_ms: 600000 max_clients: {}", clients + 64);
    EcpairdProcess m1(topology.m1(), settings);
    if (!m1.wait_for([](const StatusReply& s) { return s.master_state() == "OP"; }, 60s)) {
        throw std::runtime_error("did not reach OP:\n" + m1.log());
    }
    const auto none = measure(m1, seconds);

    std::vector<int> idle;
    for (int i = 0; i < clients; ++i) idle.push_back(connect_to(m1.socket().string()));
    const auto with_idle = measure(m1, seconds);
    const auto counted = m1.status().operator_socket().clients();

    // The same clients watching: every event goes to each of them (they read nothing; the kernel buffers).
    ecpair::control::Request watch;
    watch.mutable_watch_events();
    const auto bytes = ecpair::control::encode_delimited(watch);
    for (const int fd : idle) (void)::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    const auto with_watchers = measure(m1, seconds);
    for (const int fd : idle) ::close(fd);

    auto line = [](const char* what, const Window& w) {
        fmt::print("  {:<34} {:>7} cycles, {:>4} late, wake-up p99 {:.0f} µs (whole run)\n", what, w.cycles, w.late,
                   w.p99_us);
    };
    fmt::print("ecpaird, 33 slaves, 1 ms, {} s per window:\n", seconds);
    line("no operator clients", none);
    line(fmt::format("{} idle clients ({} counted)", clients, counted).c_str(), with_idle);
    line(fmt::format("{} watchers", clients).c_str(), with_watchers);
    return 0;
}
