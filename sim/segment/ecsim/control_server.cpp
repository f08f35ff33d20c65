// Non-blocking Unix-socket server for ecsim's line protocol.
//
// Every descriptor is non-blocking; the owner's poll() says when to read,
// write or accept. A client's bytes collect in its input buffer until a
// newline; each line is answered at once into its output buffer, which is
// written as far as the socket takes it (POLLOUT is requested while anything
// is left). Limits keep a misbehaving client from growing memory: a request
// line is at most kMaxControlLineLength characters, unsent output at most
// kMaxPendingOutput bytes, and at most kMaxClients connections are served.

#include "control_server.hpp"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "ecpair/common/log.hpp"
#include "ecpair/sim/control_protocol.hpp"

namespace ecpair::ecsim {

namespace {

constexpr std::size_t kMaxClients = 16;
constexpr std::size_t kMaxPendingOutput = 64 * 1024;
constexpr int kListenBacklog = 8;

spdlog::logger& server_log() {
    static const auto logger = ecpair::logger("ecsim");
    return *logger;
}

std::string system_reason(int error) { return std::error_code(error, std::generic_category()).message(); }

Expected<sockaddr_un, ControlServerError> socket_address(const std::filesystem::path& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string& text = path.native();
    if (text.empty() || text.size() >= sizeof(address.sun_path)) {
        return unexpected(ControlServerError{
            fmt::format("{}: a control socket path must have 1..{} characters", text, sizeof(address.sun_path) - 1)});
    }
    std::copy(text.begin(), text.end(), address.sun_path);
    return address;
}

// True when some process accepts connections on the socket at `address`.
bool someone_listens(const sockaddr_un& address) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    const bool answered = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0;
    ::close(fd);
    return answered;
}

}  // namespace

struct ControlServer::Client {
    explicit Client(int socket) : fd(socket) {}
    ~Client() { ::close(fd); }
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    int fd;
    std::string input;
    std::string output;
    bool closing = false;  // no more requests: disconnect once the output is sent
};

Expected<std::unique_ptr<ControlServer>, ControlServerError> ControlServer::listen(const std::filesystem::path& path,
                                                                                   Handler handler) {
    const auto address = socket_address(path);
    if (!address) return unexpected(address.error());

    std::error_code error;
    if (path.has_parent_path()) {
        std::filesystem::create_directories(path.parent_path(), error);
        if (error) {
            return unexpected(ControlServerError{
                fmt::format("{}: cannot create the directory: {}", path.parent_path().string(), error.message())});
        }
    }
    const auto status = std::filesystem::symlink_status(path, error);
    if (std::filesystem::exists(status)) {
        if (status.type() != std::filesystem::file_type::socket) {
            return unexpected(ControlServerError{fmt::format("{}: exists and is not a socket", path.string())});
        }
        if (someone_listens(*address)) {
            return unexpected(
                ControlServerError{fmt::format("{}: another process already answers on this socket", path.string())});
        }
        std::filesystem::remove(path, error);  // a stale socket of a process that is gone
    }

    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return unexpected(ControlServerError{fmt::format("{}: socket(): {}", path.string(), system_reason(errno))});
    }
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&*address), sizeof(*address)) != 0 ||
        ::listen(fd, kListenBacklog) != 0) {
        const int reason = errno;
        ::close(fd);
        return unexpected(
            ControlServerError{fmt::format("{}: cannot listen: {}", path.string(), system_reason(reason))});
    }
    return std::unique_ptr<ControlServer>(new ControlServer(path, fd, std::move(handler)));
}

ControlServer::ControlServer(std::filesystem::path path, int listen_fd, Handler handler)
    : path_(std::move(path)), listen_fd_(listen_fd), handler_(std::move(handler)) {}

ControlServer::~ControlServer() {
    clients_.clear();
    ::close(listen_fd_);
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
}

std::size_t ControlServer::append_poll_fds(std::vector<pollfd>& fds) const {
    fds.push_back(pollfd{listen_fd_, POLLIN, 0});
    for (const auto& client : clients_) {
        short events = client->closing ? short{0} : short{POLLIN};
        if (!client->output.empty()) events = static_cast<short>(events | POLLOUT);
        fds.push_back(pollfd{client->fd, events, 0});
    }
    return 1 + clients_.size();
}

void ControlServer::on_poll(std::span<const pollfd> fds) {
    // The clients first: their entries follow the listener's in the order
    // append_poll_fds() wrote them, and accepting would add clients.
    for (std::size_t i = 0; i < clients_.size() && i + 1 < fds.size(); ++i) {
        Client& client = *clients_[i];
        const short revents = fds[i + 1].revents;
        if (revents == 0) continue;
        bool keep = true;
        if ((revents & (POLLIN | POLLHUP | POLLERR)) != 0) keep = serve(client);
        if (keep && (revents & POLLOUT) != 0) keep = flush(client);
        if (!keep) {
            client.closing = true;
            client.output.clear();
        }
    }
    std::erase_if(clients_, [](const auto& client) { return client->closing && client->output.empty(); });
    if (!fds.empty() && (fds[0].revents & POLLIN) != 0) accept_clients();
}

void ControlServer::accept_clients() {
    for (;;) {
        const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
                server_log().warn("control socket {}: accept: {}", path_.string(), system_reason(errno));
            }
            return;
        }
        if (clients_.size() >= kMaxClients) {
            const std::string refusal = sim::control_error("too many control connections") + "\n";
            (void)::send(fd, refusal.data(), refusal.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
            ::close(fd);
            continue;
        }
        clients_.push_back(std::make_unique<Client>(fd));
    }
}

bool ControlServer::serve(Client& client) {
    char chunk[512];
    bool peer_closed = false;
    for (;;) {
        const ssize_t n = ::recv(client.fd, chunk, sizeof(chunk), 0);
        if (n > 0) {
            client.input.append(chunk, static_cast<std::size_t>(n));
            if (client.input.size() > 4 * sim::kMaxControlLineLength) break;  // enough to judge; rest next time
            continue;
        }
        if (n == 0) {
            peer_closed = true;
        } else if (errno == EINTR) {
            continue;
        } else if (errno != EAGAIN && errno != EWOULDBLOCK) {
            return false;
        }
        break;
    }

    std::size_t newline;
    while (!client.closing && (newline = client.input.find('\n')) != std::string::npos) {
        const std::string line = client.input.substr(0, newline);
        client.input.erase(0, newline + 1);
        client.output += handler_(line);
        client.output += '\n';
    }
    if (!client.closing && client.input.size() > sim::kMaxControlLineLength + 1) {
        client.output += sim::control_error(
            fmt::format("request line longer than {} characters; disconnecting", sim::kMaxControlLineLength));
        client.output += '\n';
        client.closing = true;
        client.input.clear();
    }
    if (peer_closed) client.closing = true;
    if (client.output.size() > kMaxPendingOutput) return false;  // the client does not read its answers
    return flush(client);
}

bool ControlServer::flush(Client& client) {
    while (!client.output.empty()) {
        const ssize_t n = ::send(client.fd, client.output.data(), client.output.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            client.output.erase(0, static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
        return false;
    }
    return true;
}

}  // namespace ecpair::ecsim
