#pragma once
// A ControlServer on a socket in a temporary directory, served by its own
// io_context thread, answering through a small fake handler; and raw client
// sockets for tests that misbehave on purpose.

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <future>
#include <string>
#include <thread>

#include <catch2/catch.hpp>

#include "ecpair/control/control_client.hpp"
#include "ecpair/control/control_server.hpp"
#include "ecpair/control/delimited.hpp"
#include "temp_dir.hpp"

namespace ecpair::control::test {

class FakeHandler final : public ControlHandler {
public:
    FakeHandler() {
        reply.set_name("fake");
        reply.set_master_state("OP");
    }
    StatusReply status(const StatusRequest&) override { return reply; }
    std::optional<std::string> set_master_state(const SetMasterStateRequest&) override { return std::nullopt; }
    std::optional<std::string> set_red_state(const SetRedStateRequest&) override { return "not a pair"; }
    ImageHistoryReply image_history(const ImageHistoryRequest&) override { return {}; }
    std::optional<std::string> switchover(const SwitchoverRequest&) override { return "not a pair"; }
    std::optional<std::string> force_standby(const ForceStandbyRequest&) override { return "not a pair"; }

    StatusReply reply;  // what status() answers; set it before the server runs
};

// Connects without any protocol; the descriptor, or -errno.
inline int connect_raw(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -errno;
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        const int error = errno;
        ::close(fd);
        return -error;
    }
    return fd;
}

// Waits (bounded) for the server to close `fd`; true when it did. Data
// before the end (an error response) is skipped.
inline bool closed_by_server(int fd, std::chrono::milliseconds patience = std::chrono::seconds(10)) {
    const auto deadline = std::chrono::steady_clock::now() + patience;
    char buffer[4096];
    while (std::chrono::steady_clock::now() < deadline) {
        pollfd entry{fd, POLLIN, 0};
        if (::poll(&entry, 1, 100) <= 0) continue;
        const auto n = ::recv(fd, buffer, sizeof(buffer), 0);
        if (n == 0 || (n < 0 && errno == ECONNRESET)) return true;
    }
    return false;
}

// Reads one whole Response from a raw client socket (bounded wait).
inline std::optional<Response> read_response(int fd, std::chrono::milliseconds patience = std::chrono::seconds(10)) {
    DelimitedReader reader;
    const auto deadline = std::chrono::steady_clock::now() + patience;
    std::string payload;
    char buffer[4096];
    while (std::chrono::steady_clock::now() < deadline) {
        if (reader.next(payload) == DelimitedReader::Result::Message) {
            Response response;
            if (!response.ParseFromString(payload)) return std::nullopt;
            return response;
        }
        pollfd entry{fd, POLLIN, 0};
        if (::poll(&entry, 1, 100) <= 0) continue;
        const auto n = ::recv(fd, buffer, sizeof(buffer), 0);
        if (n <= 0) return std::nullopt;
        reader.feed(std::string_view(buffer, static_cast<std::size_t>(n)));
    }
    return std::nullopt;
}

struct ServerFixture {
    explicit ServerFixture(SocketSettings settings = {}, const StatusReply* reply = nullptr) {
        if (reply != nullptr) handler.reply = *reply;
        settings.path = (dir / "op.sock").string();
        path = settings.path;
        server = std::make_unique<ControlServer>(io, handler, settings);
        auto opened = server->open();
        if (!opened) FAIL(opened.error());
        thread = std::thread([this] { io.run(); });
    }
    // Runs `f` on the server's thread and waits for it.
    template <class F>
    auto on_io(F f) {
        std::packaged_task<decltype(f())()> task(std::move(f));
        auto result = task.get_future();
        boost::asio::post(io, [&task] { task(); });
        return result.get();
    }

    ~ServerFixture() {
        on_io([this] { server.reset(); });
        work.reset();
        io.stop();
        thread.join();
    }

    // Waits (bounded) until the server counts `n` clients.
    bool wait_for_clients(std::size_t n) {
        for (int attempt = 0; attempt < 500; ++attempt) {
            if (on_io([this] { return server->clients(); }) == n) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

    StatusReply status() const {
        Request request;
        request.mutable_status();
        auto response = call(path, request);
        if (!response) FAIL(response.error().message);
        REQUIRE(response->ok());
        return response->status();
    }

    ecpair::test::TempDir dir{"ecpair-control"};
    std::string path;
    boost::asio::io_context io;
    boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work{io.get_executor()};
    FakeHandler handler;
    std::unique_ptr<ControlServer> server;
    std::thread thread;
};

}  // namespace ecpair::control::test
