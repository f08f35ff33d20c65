// ecpaird's systemd notifications without systemd: READY with a status
// line, WATCHDOG=1 only for a look at which the cycle advanced, STATUS when
// it changes, STOPPING; and the journal-stream check of systemd.exec(5).

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <vector>

#include "ecpair/systemd/journal.hpp"
#include "ecpair/systemd/service_notifier.hpp"
#include "temp_dir.hpp"

using ecpair::systemd::ServiceNotifier;
using namespace std::chrono_literals;

namespace {

struct Fixture {
    ServiceNotifier make(std::optional<std::chrono::microseconds> watchdog) {
        return ServiceNotifier(
            io, watchdog, [this](const std::string& s) { sent.push_back(s); }, [this] { return cycle; },
            [this] { return status; });
    }
    boost::asio::io_context io;
    std::vector<std::string> sent;
    std::uint64_t cycle = 100;
    std::string status = "ACTIVE, master OP";
};

}  // namespace

TEST_CASE_METHOD(Fixture, "systemd: READY with the status, then WATCHDOG only while the cycle advances", "[systemd]") {
    auto notifier = make(3s);
    notifier.ready();
    REQUIRE(sent == std::vector<std::string>{"READY=1\nSTATUS=ACTIVE, master OP"});

    cycle = 150;
    notifier.watch();
    CHECK(sent.back() == "WATCHDOG=1");
    sent.clear();
    notifier.watch();  // stands still
    notifier.watch();
    CHECK(sent.empty());
    CHECK(notifier.watchdog_pings() == 1);
    CHECK(notifier.watchdog_withheld() == 2);
    cycle = 151;
    notifier.watch();
    CHECK(sent == std::vector<std::string>{"WATCHDOG=1"});
}

TEST_CASE_METHOD(Fixture, "systemd: a changed status line goes with the next look, a ping or not", "[systemd]") {
    auto notifier = make(3s);
    notifier.ready();
    sent.clear();
    status = "INACTIVE, master OP";
    notifier.watch();  // the cycle stood still: no ping, but the new status
    CHECK(sent == std::vector<std::string>{"STATUS=INACTIVE, master OP"});
    cycle = 200;
    status = "ACTIVE, master OP";
    notifier.watch();
    CHECK(sent.back() == "WATCHDOG=1\nSTATUS=ACTIVE, master OP");
}

TEST_CASE_METHOD(Fixture, "systemd: STOPPING ends the pings", "[systemd]") {
    auto notifier = make(3s);
    notifier.ready();
    notifier.stopping();
    CHECK(sent.back() == "STOPPING=1\nSTATUS=stopping");
    cycle = 300;
    notifier.watch();
    CHECK(sent.back() == "STOPPING=1\nSTATUS=stopping");
}

TEST_CASE_METHOD(Fixture, "systemd: outside systemd nothing is armed", "[systemd]") {
    ::unsetenv("WATCHDOG_USEC");
    ::unsetenv("NOTIFY_SOCKET");
    auto notifier = ServiceNotifier::from_environment(io, [] { return std::uint64_t{1}; }, [] { return std::string("x"); });
    CHECK_FALSE(notifier->watchdog_interval());
    notifier->ready();  // sd_notify without NOTIFY_SOCKET: nothing, no error
    CHECK(io.poll() == 0);  // no timer was armed
}

TEST_CASE("systemd: the journal stream is recognised by device and inode", "[systemd]") {
    ecpair::test::TempDir dir{"ecpair-journal"};
    const auto file = (dir / "stream").string();
    const int fd = ::open(file.c_str(), O_CREAT | O_WRONLY | O_CLOEXEC, 0600);
    REQUIRE(fd >= 0);
    struct stat info {};
    REQUIRE(::fstat(fd, &info) == 0);
    const auto same = fmt::format("{}:{}", info.st_dev, info.st_ino);
    const auto other = fmt::format("{}:{}", info.st_dev, info.st_ino + 1);
    CHECK(ecpair::systemd::is_journal_stream(fd, same.c_str()));
    CHECK_FALSE(ecpair::systemd::is_journal_stream(fd, other.c_str()));
    CHECK_FALSE(ecpair::systemd::is_journal_stream(fd, "garbage"));
    CHECK_FALSE(ecpair::systemd::is_journal_stream(fd, nullptr));
    ::close(fd);
}
