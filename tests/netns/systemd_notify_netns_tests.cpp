// The real ecpaird under a stand-in for systemd: a datagram socket as
// $NOTIFY_SOCKET and $WATCHDOG_USEC set. It must say READY=1 once it runs,
// WATCHDOG=1 every WatchdogSec/3 while it runs, nothing while it is stopped
// (SIGSTOP), pings again after SIGCONT, and STOPPING=1 on SIGTERM.

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>

#include "ecpaird_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;

namespace {

// A bound AF_UNIX datagram socket that collects what sd_notify sends.
class NotifySocket {
public:
    explicit NotifySocket(std::string path) : path_(std::move(path)) {
        fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        std::memcpy(address.sun_path, path_.c_str(), path_.size() + 1);
        REQUIRE(::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0);
    }
    ~NotifySocket() { ::close(fd_); }

    // The next datagram within `patience`, or nullopt.
    std::optional<std::string> next(std::chrono::milliseconds patience) {
        pollfd entry{fd_, POLLIN, 0};
        if (::poll(&entry, 1, static_cast<int>(patience.count())) <= 0) return std::nullopt;
        char buffer[4096];
        const auto n = ::recv(fd_, buffer, sizeof(buffer), 0);
        if (n <= 0) return std::nullopt;
        return std::string(buffer, static_cast<std::size_t>(n));
    }
    // Waits for a datagram containing `text`; the ones before it are dropped.
    bool wait_for(const std::string& text, std::chrono::milliseconds patience) {
        const auto deadline = std::chrono::steady_clock::now() + patience;
        while (std::chrono::steady_clock::now() < deadline) {
            const auto got = next(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()));
            if (got && got->find(text) != std::string::npos) return true;
        }
        return false;
    }
    void drain() {
        while (next(0ms)) {
        }
    }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    int fd_ = -1;
};

// Every thread of `pid` is stopped (state T in /proc): it sends nothing more.
bool all_threads_stopped(pid_t pid) {
    const std::filesystem::path tasks = "/proc/" + std::to_string(pid) + "/task";
    for (const auto& task : std::filesystem::directory_iterator(tasks)) {
        std::ifstream stat(task.path() / "stat");
        std::string line;
        std::getline(stat, line);
        const auto after_name = line.rfind(')');
        if (after_name == std::string::npos || line.size() < after_name + 3 || line[after_name + 2] != 'T') return false;
    }
    return true;
}

}  // namespace

TEST_CASE("systemd notify: READY, WATCHDOG while running, none while stopped, STOPPING", "[netns][systemd]") {
    TempDir dir{"ecpair-notify"};
    RingTopology topology(Controllers::Single);
    NotifySocket notify((dir / "notify.sock").string());
    EcpairdSettings settings;
    settings.eni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");
    settings.dir = dir.path();
    // The child inherits the environment at its start; nothing else here starts children meanwhile.
    ::setenv("NOTIFY_SOCKET", notify.path().c_str(), 1);
    ::setenv("WATCHDOG_USEC", "300000", 1);
    std::optional<EcpairdProcess> m1;
    try {
        m1.emplace(topology.m1(), settings);
    } catch (...) {
        ::unsetenv("NOTIFY_SOCKET");
        ::unsetenv("WATCHDOG_USEC");
        throw;
    }
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");

    REQUIRE(notify.wait_for("READY=1", 10s));
    CHECK(notify.wait_for("WATCHDOG=1", 5s));
    CHECK(notify.wait_for("WATCHDOG=1", 5s));

    REQUIRE(::kill(m1->pid(), SIGSTOP) == 0);
    for (int look = 0; look < 500 && !all_threads_stopped(m1->pid()); ++look) std::this_thread::sleep_for(10ms);
    REQUIRE(all_threads_stopped(m1->pid()));
    notify.drain();
    CHECK_FALSE(notify.next(1s));  // three watchdog periods without a word
    REQUIRE(::kill(m1->pid(), SIGCONT) == 0);
    CHECK(notify.wait_for("WATCHDOG=1", 5s));

    REQUIRE(::kill(m1->pid(), SIGTERM) == 0);
    CHECK(notify.wait_for("STOPPING=1", 5s));
    CHECK(m1->wait_for_exit(10s) == 0);
}
