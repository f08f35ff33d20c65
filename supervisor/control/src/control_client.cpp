#include "ecpair/control/control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "ecpair/control/delimited.hpp"

namespace ecpair::control {
namespace detail {

class Connection {
public:
    explicit Connection(const std::string& path) : path_(path), fd_(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0)) {}
    ~Connection() {
        if (fd_ >= 0) ::close(fd_);
    }

    Expected<void, ClientError> connect() {
        if (fd_ < 0) return fail("socket");
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        if (path_.size() >= sizeof(address.sun_path)) return unexpected(ClientError{path_ + ": path too long"});
        std::memcpy(address.sun_path, path_.c_str(), path_.size() + 1);
        if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) return fail("connect");
        return {};
    }

    Expected<void, ClientError> send(const Request& request) {
        const std::string bytes = encode_delimited(request);
        std::size_t sent = 0;
        while (sent < bytes.size()) {
            const auto n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
            if (n < 0) {
                if (errno == EINTR) continue;
                return fail("send");
            }
            sent += static_cast<std::size_t>(n);
        }
        return {};
    }

    // The next response; nullopt when the deadline passed or the server closed.
    Expected<std::optional<Response>, ClientError> receive(std::chrono::steady_clock::time_point deadline) {
        std::string payload;
        for (;;) {
            switch (reader_.next(payload)) {
                case DelimitedReader::Result::Message: {
                    Response response;
                    if (!response.ParseFromString(payload)) {
                        return unexpected(ClientError{path_ + ": the server sent an unreadable response"});
                    }
                    return std::optional<Response>(std::move(response));
                }
                case DelimitedReader::Result::Error: return unexpected(ClientError{path_ + ": " + reader_.error()});
                case DelimitedReader::Result::NeedMore: break;
            }
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
            if (left.count() <= 0) return std::optional<Response>();
            pollfd pfd{fd_, POLLIN, 0};
            const int ready = ::poll(&pfd, 1, static_cast<int>(std::min<std::int64_t>(left.count(), 1000)));
            if (ready < 0 && errno != EINTR) return fail("poll");
            if (ready <= 0) continue;
            std::array<char, 4096> buffer{};
            const auto n = ::recv(fd_, buffer.data(), buffer.size(), 0);
            if (n < 0 && errno != EINTR) return fail("recv");
            if (n == 0) return std::optional<Response>();
            if (n > 0) reader_.feed(std::string_view(buffer.data(), static_cast<std::size_t>(n)));
        }
    }

    int fd() const { return fd_; }

    // Every whole response already received, without waiting; an error when
    // the server closed the connection or sent something unreadable.
    Expected<std::vector<Response>, ClientError> receive_available() {
        std::array<char, 4096> buffer{};
        bool closed = false;
        for (;;) {
            const auto n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
            if (n > 0) {
                reader_.feed(std::string_view(buffer.data(), static_cast<std::size_t>(n)));
                continue;
            }
            if (n == 0) closed = true;
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) return fail("recv");
            break;
        }
        std::vector<Response> responses;
        std::string payload;
        for (;;) {
            const auto result = reader_.next(payload);
            if (result == DelimitedReader::Result::NeedMore) break;
            if (result == DelimitedReader::Result::Error) return unexpected(ClientError{path_ + ": " + reader_.error()});
            Response response;
            if (!response.ParseFromString(payload)) {
                return unexpected(ClientError{path_ + ": the server sent an unreadable response"});
            }
            responses.push_back(std::move(response));
        }
        if (closed && responses.empty()) return unexpected(ClientError{path_ + ": ecpaird closed the connection"});
        return responses;
    }

private:
    Unexpected<ClientError> fail(const char* what) const {
        return unexpected(ClientError{fmt::format("{}: {} failed: {}", path_, what, std::strerror(errno))});
    }

    std::string path_;
    int fd_;
    DelimitedReader reader_;
};

}  // namespace detail

using detail::Connection;

EventSubscription::EventSubscription(std::unique_ptr<detail::Connection> connection)
    : connection_(std::move(connection)) {}
EventSubscription::EventSubscription(EventSubscription&&) noexcept = default;
EventSubscription& EventSubscription::operator=(EventSubscription&&) noexcept = default;
EventSubscription::~EventSubscription() = default;

Expected<EventSubscription, ClientError> EventSubscription::open(const std::string& socket_path) {
    auto connection = std::make_unique<Connection>(socket_path);
    if (auto c = connection->connect(); !c) return unexpected(c.error());
    Request request;
    request.mutable_watch_events();
    if (auto s = connection->send(request); !s) return unexpected(s.error());
    return EventSubscription(std::move(connection));
}

int EventSubscription::fd() const { return connection_->fd(); }

Expected<std::vector<Response>, ClientError> EventSubscription::take() { return connection_->receive_available(); }

Expected<Response, ClientError> call(const std::string& socket_path, const Request& request,
                                     std::chrono::milliseconds timeout) {
    Connection connection(socket_path);
    if (auto c = connection.connect(); !c) return unexpected(c.error());
    if (auto s = connection.send(request); !s) {
        // A server that refuses at once (busy) answers and closes before the
        // request is written: its answer is still waiting to be read.
        auto early = connection.receive(std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
        if (early && early->has_value()) return std::move(**early);
        return unexpected(s.error());
    }
    auto response = connection.receive(std::chrono::steady_clock::now() + timeout);
    if (!response) return unexpected(response.error());
    if (!response->has_value()) return unexpected(ClientError{socket_path + ": no response from ecpaird"});
    return std::move(**response);
}

Expected<void, ClientError> stream(const std::string& socket_path, const Request& request,
                                   const std::function<bool(const Response&)>& on_response,
                                   std::chrono::milliseconds duration) {
    Connection connection(socket_path);
    if (auto c = connection.connect(); !c) return unexpected(c.error());
    if (auto s = connection.send(request); !s) return unexpected(s.error());
    const auto end = duration.count() > 0 ? std::chrono::steady_clock::now() + duration
                                          : std::chrono::steady_clock::time_point::max();
    for (;;) {
        auto response = connection.receive(end);
        if (!response) return unexpected(response.error());
        if (!response->has_value()) return {};
        if (!on_response(**response)) return {};
    }
}

}  // namespace ecpair::control
