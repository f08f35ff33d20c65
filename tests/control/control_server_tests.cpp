// The operator socket's hardening, without network namespaces: the file's
// mode and group are what the config says and another user is refused by
// them (a child running as `nobody`); a client that sends nothing or half a
// request is disconnected after request_timeout while a watcher is not;
// beyond max_clients a client is told "busy"; a watcher that does not read
// is dropped; a thousand idle clients do not keep the server from answering.

#include <grp.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <vector>

#include "control_server_fixture.hpp"

using namespace ecpair::control;
using namespace ecpair::control::test;
using namespace std::chrono_literals;

namespace {

constexpr uid_t kNobody = 65534;
constexpr gid_t kNogroup = 65534;

// Connects to `path` as nobody:nogroup (no supplementary groups) in a child
// process: 0 when it could connect, else the errno. Only system calls after
// fork: the test process has other threads.
int connect_as_nobody(const std::string& path) {
    const pid_t child = ::fork();
    if (child == 0) {
        if (::setgroups(0, nullptr) != 0 || ::setgid(kNogroup) != 0 || ::setuid(kNobody) != 0) ::_exit(200);
        const int fd = connect_raw(path);
        ::_exit(fd >= 0 ? 0 : -fd);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 255;
}

SocketSettings with_mode(unsigned mode, const std::string& group = "") {
    SocketSettings s;
    s.mode = mode;
    s.group = group;
    return s;
}

bool is_root() { return ::geteuid() == 0; }

}  // namespace

TEST_CASE("operator socket: the file has the configured mode and group", "[control]") {
    ServerFixture f(with_mode(0640, "nogroup"));
    struct stat info {};
    REQUIRE(::stat(f.path.c_str(), &info) == 0);
    CHECK(S_ISSOCK(info.st_mode));
    CHECK((info.st_mode & 07777) == 0640);
    CHECK(info.st_gid == ::getgrnam("nogroup")->gr_gid);
}

TEST_CASE("operator socket: another user is refused unless mode and group let them in", "[control]") {
    if (!is_root()) {
        WARN("needs root to run a child as another user");
        return;
    }
    SECTION("mode 0660, the daemon's group: nobody is refused") {
        ServerFixture f(with_mode(0660));
        std::filesystem::permissions(f.dir.path(), std::filesystem::perms::all);  // the directory is no obstacle
        CHECK(connect_as_nobody(f.path) == EACCES);
        CHECK(connect_raw(f.path) >= 0);  // its owner connects
    }
    SECTION("mode 0660, group nogroup: nobody, a member, may connect") {
        ServerFixture f(with_mode(0660, "nogroup"));
        std::filesystem::permissions(f.dir.path(), std::filesystem::perms::all);
        CHECK(connect_as_nobody(f.path) == 0);
    }
    SECTION("mode 0666: anybody may connect (so the refusals above are the mode's)") {
        ServerFixture f(with_mode(0666));
        std::filesystem::permissions(f.dir.path(), std::filesystem::perms::all);
        CHECK(connect_as_nobody(f.path) == 0);
    }
}

TEST_CASE("operator socket: an unknown group is a config error naming it", "[control]") {
    ecpair::test::TempDir dir{"ecpair-control"};
    boost::asio::io_context io;
    FakeHandler handler;
    SocketSettings settings = with_mode(0660, "no-such-group-here");
    settings.path = (dir / "op.sock").string();
    ControlServer server(io, handler, settings);
    auto opened = server.open();
    REQUIRE_FALSE(opened);
    CHECK(opened.error() == "control.group: no group named 'no-such-group-here'");
    CHECK_FALSE(std::filesystem::exists(settings.path));
}

TEST_CASE("operator socket: a client that sends nothing or half a request is disconnected", "[control]") {
    SocketSettings settings;
    settings.request_timeout = 200ms;
    ServerFixture f(settings);

    const int silent = connect_raw(f.path);
    REQUIRE(silent >= 0);
    const int half = connect_raw(f.path);
    REQUIRE(half >= 0);
    Request request;
    request.mutable_status();
    const auto bytes = encode_delimited(request);
    REQUIRE(bytes.size() >= 2);
    REQUIRE(::send(half, bytes.data(), 1, 0) == 1);  // the length, not the message

    CHECK(closed_by_server(silent));
    CHECK(closed_by_server(half));
    ::close(silent);
    ::close(half);
    CHECK(f.status().operator_socket().timed_out() == 2);
}

TEST_CASE("operator socket: a watcher stays connected past the request timeout", "[control]") {
    SocketSettings settings;
    settings.request_timeout = 100ms;
    ServerFixture f(settings);
    Request request;
    request.mutable_watch_events();
    std::vector<std::string> seen;
    std::thread publisher([&f] {
        std::this_thread::sleep_for(500ms);  // five request timeouts
        f.on_io([&f] {
            EventMessage event;
            event.set_kind("line-break");
            event.set_text("cycle 7: line break after slave 2");
            f.server->publish(event);
        });
    });
    auto streamed = stream(
        f.path, request,
        [&seen](const Response& r) {
            if (r.has_event()) seen.push_back(r.event().text());
            return seen.empty();
        },
        10s);
    publisher.join();
    REQUIRE(streamed);
    REQUIRE(seen.size() == 1);
    CHECK(seen[0] == "cycle 7: line break after slave 2");
    CHECK(f.status().operator_socket().timed_out() == 0);
}

TEST_CASE("operator socket: beyond max_clients a client is told the server is busy", "[control]") {
    SocketSettings settings;
    settings.max_clients = 3;
    ServerFixture f(settings);
    std::vector<int> held;
    for (int i = 0; i < 3; ++i) held.push_back(connect_raw(f.path));
    for (const int fd : held) REQUIRE(fd >= 0);
    REQUIRE(f.wait_for_clients(3));

    Request request;
    request.mutable_status();
    auto response = call(f.path, request);
    REQUIRE(response);
    CHECK_FALSE(response->ok());
    CHECK(response->error() == "busy: 3 operator clients are connected already (control.max_clients)");
    for (const int fd : held) ::close(fd);
    // Once they left, it answers again.
    std::optional<Response> answered;
    for (int attempt = 0; attempt < 100 && !answered; ++attempt) {
        auto again = call(f.path, request);
        if (again && again->ok()) answered = *again;
        else std::this_thread::sleep_for(20ms);
    }
    REQUIRE(answered);
    CHECK(answered->status().operator_socket().refused_busy() >= 1);
}

TEST_CASE("operator socket: a watcher that does not read its events is dropped", "[control]") {
    ServerFixture f;
    const int watcher = connect_raw(f.path);
    REQUIRE(watcher >= 0);
    Request request;
    request.mutable_watch_events();
    const auto bytes = encode_delimited(request);
    REQUIRE(::send(watcher, bytes.data(), bytes.size(), 0) == static_cast<ssize_t>(bytes.size()));
    // Once the server answered, it knows the client watches: then publish far
    // more than the socket holds, and read nothing more.
    const auto answer = read_response(watcher);
    REQUIRE(answer);
    REQUIRE(answer->ok());
    f.on_io([&f] {
        EventMessage event;
        event.set_kind("frame-lost");
        event.set_text(std::string(200, 'x'));
        for (std::size_t i = 0; i < 4 * ControlServer::kMaxQueued; ++i) f.server->publish(event);
    });
    CHECK(f.status().operator_socket().slow_watchers() == 1);
    CHECK(closed_by_server(watcher));
    ::close(watcher);
}

TEST_CASE("operator socket: a thousand idle clients do not keep it from answering", "[control]") {
    rlimit limit{};
    REQUIRE(::getrlimit(RLIMIT_NOFILE, &limit) == 0);
    limit.rlim_cur = std::max<rlim_t>(limit.rlim_cur, std::min<rlim_t>(limit.rlim_max, 4096));
    ::setrlimit(RLIMIT_NOFILE, &limit);
    REQUIRE(limit.rlim_cur >= 1100);

    ServerFixture f;
    std::vector<int> idle;
    for (int i = 0; i < 1000; ++i) {
        const int fd = connect_raw(f.path);
        REQUIRE(fd >= 0);
        idle.push_back(fd);
    }
    const auto status = f.status();
    CHECK(status.name() == "fake");
    CHECK(status.operator_socket().clients() >= 1000);
    CHECK(status.operator_socket().refused_busy() == 0);
    for (const int fd : idle) ::close(fd);
}
