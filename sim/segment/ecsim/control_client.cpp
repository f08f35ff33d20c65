// One request, one response: connect, write the line, read up to the first
// newline (waiting at most kResponseTimeout in poll()), print it (with
// --json, what follows "ok ").

#include "control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

namespace ecpair::ecsim {

namespace {

constexpr std::chrono::milliseconds kResponseTimeout{5000};

int fail(const std::string& message) {
    std::fprintf(stderr, "ecsim ctl: %s\n", message.c_str());
    return kExitUnreachable;
}

std::string reason(int error) { return std::error_code(error, std::generic_category()).message(); }

class Socket {
public:
    explicit Socket(int fd) : fd_(fd) {}
    ~Socket() {
        if (fd_ >= 0) ::close(fd_);
    }
    Socket(const Socket&) = delete;
    Socket& operator=(const Socket&) = delete;
    int fd() const { return fd_; }

private:
    int fd_;
};

}  // namespace

int run_control_client(const CtlOptions& options) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string& path = options.control.native();
    if (path.empty() || path.size() >= sizeof(address.sun_path)) return fail(path + ": not a usable socket path");
    std::memcpy(address.sun_path, path.data(), path.size());

    Socket socket(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (socket.fd() < 0) return fail("socket(): " + reason(errno));
    if (::connect(socket.fd(), reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        return fail(path + ": " + reason(errno) + " (is ecsim running?)");
    }

    const std::string request = options.request + "\n";
    std::size_t sent = 0;
    while (sent < request.size()) {
        const ssize_t n = ::send(socket.fd(), request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return fail(path + ": send: " + reason(errno));
        sent += static_cast<std::size_t>(n);
    }

    std::string response;
    const auto deadline = std::chrono::steady_clock::now() + kResponseTimeout;
    while (response.find('\n') == std::string::npos) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) return fail(path + ": no response within 5 s");
        pollfd wait{socket.fd(), POLLIN, 0};
        const int ready = ::poll(&wait, 1, static_cast<int>(left.count()));
        if (ready < 0 && errno == EINTR) continue;
        if (ready < 0) return fail(path + ": poll: " + reason(errno));
        if (ready == 0) continue;
        char chunk[4096];
        const ssize_t n = ::recv(socket.fd(), chunk, sizeof(chunk), 0);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return fail(path + ": recv: " + reason(errno));
        if (n == 0) break;
        response.append(chunk, static_cast<std::size_t>(n));
    }
    const auto newline = response.find('\n');
    if (newline == std::string::npos) return fail(path + ": the connection closed before a complete response");
    response.resize(newline);

    const bool ok = response == "ok" || response.rfind("ok ", 0) == 0;
    // --json: the JSON alone, for a script's parser (the exit status says ok).
    const std::string shown = options.json && ok && response.size() > 3 ? response.substr(3) : response;
    std::printf("%s\n", shown.c_str());
    std::fflush(stdout);
    return ok ? kExitOk : kExitFailure;
}

}  // namespace ecpair::ecsim
