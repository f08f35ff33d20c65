// The real ecpaird's operator socket under a thousand idle clients: it still
// answers, counts them, and its cycle keeps advancing. (How many cycles come
// late with and without them is a figure of bench/operator_socket_bench.sh,
// not an assertion.)

#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <iostream>

#include <catch2/catch.hpp>

#include "ecpaird_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::StatusReply;

namespace {

int connect_idle(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

}  // namespace

TEST_CASE("operator socket: 1,000 idle clients, and ecpaird still answers while its cycle advances",
          "[netns][socket]") {
    rlimit limit{};
    REQUIRE(::getrlimit(RLIMIT_NOFILE, &limit) == 0);
    limit.rlim_cur = std::max<rlim_t>(limit.rlim_cur, std::min<rlim_t>(limit.rlim_max, 4096));
    ::setrlimit(RLIMIT_NOFILE, &limit);
    REQUIRE(limit.rlim_cur >= 1100);

    TempDir dir{"ecpair-socket"};
    RingTopology topology(Controllers::Single);
    EcpairdSettings settings;
    settings.eni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");
    settings.dir = dir.path();
    settings.extra_config = "cycle_time_us: 1000\n";
    settings.control_extra = "request_timeout_ms: 600000";  // they stay for the whole test
    EcpairdProcess m1(topology.m1(), settings);
    const auto before = m1.wait_for([](const StatusReply& s) { return s.timing().cycles() > 500; }, 20s);
    REQUIRE(before);

    std::vector<int> idle;
    for (int i = 0; i < 1000; ++i) {
        const int fd = connect_idle(m1.socket().string());
        REQUIRE(fd >= 0);
        idle.push_back(fd);
    }
    const auto cycles_then = m1.status().timing().cycles();
    const auto after = m1.wait_for(
        [&](const StatusReply& s) {
            return s.operator_socket().clients() >= 1001 && s.timing().cycles() > cycles_then + 1000;
        },
        30s);
    REQUIRE(after);
    CHECK(after->operator_socket().refused_busy() == 0);
    CHECK(after->operator_socket().timed_out() == 0);
    std::cout << "operator socket: " << after->operator_socket().clients() << " clients; late cycles "
              << before->timing().late() << " before, " << after->timing().late() << " after" << std::endl;
    for (const int fd : idle) ::close(fd);
    CHECK(m1.wait_for([](const StatusReply& s) { return s.operator_socket().clients() == 1; }, 20s));
}
