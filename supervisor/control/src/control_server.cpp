// One Session per client: it reads requests with the incremental delimited
// reader, answers each, and keeps a queue of outgoing messages so that an
// event published while a write is in flight is not interleaved with it.
// A client that sends garbage gets one error Response and is closed.

#include "ecpair/control/control_server.hpp"

#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <filesystem>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/control/delimited.hpp"

namespace ecpair::control {

namespace asio = boost::asio;
using stream_protocol = asio::local::stream_protocol;

class ControlServer::Session : public std::enable_shared_from_this<Session> {
public:
    Session(stream_protocol::socket socket, ControlHandler& handler, const std::deque<EventMessage>& backlog)
        : socket_(std::move(socket)), handler_(handler), backlog_(backlog) {}

    void start() { read(); }
    bool watching() const { return watching_; }

    void send(const Response& response) {
        const bool idle = outbox_.empty();
        outbox_.push_back(encode_delimited(response));
        if (idle) write();
    }

private:
    void read() {
        auto self = shared_from_this();
        socket_.async_read_some(asio::buffer(buffer_), [this, self](const boost::system::error_code& ec, std::size_t n) {
            if (ec) return;  // closed: the session ends with its last reference
            reader_.feed(std::string_view(buffer_.data(), n));
            std::string payload;
            for (;;) {
                const auto result = reader_.next(payload);
                if (result == DelimitedReader::Result::NeedMore) break;
                if (result == DelimitedReader::Result::Error) {
                    reject(reader_.error());
                    return;
                }
                Request request;
                if (!request.ParseFromString(payload)) {
                    reject("the request is not an ecpair.control.Request");
                    return;
                }
                handle(request);
            }
            read();
        });
    }

    void handle(const Request& request) {
        Response response;
        switch (request.kind_case()) {
            case Request::kStatus:
                *response.mutable_status() = handler_.status(request.status());
                response.set_ok(true);
                break;
            case Request::kWatchEvents:
                watching_ = true;
                response.set_ok(true);
                send(response);
                for (const auto& event : backlog_) {
                    Response past;
                    past.set_ok(true);
                    *past.mutable_event() = event;
                    send(past);
                }
                return;
            case Request::kSetMasterState: answer(response, handler_.set_master_state(request.set_master_state())); break;
            case Request::kSetRedState: answer(response, handler_.set_red_state(request.set_red_state())); break;
            case Request::kImageHistory:
                *response.mutable_image_history() = handler_.image_history(request.image_history());
                response.set_ok(true);
                break;
            case Request::kSwitchover: answer(response, handler_.switchover(request.switchover())); break;
            case Request::kForceStandby: answer(response, handler_.force_standby(request.force_standby())); break;
            case Request::KIND_NOT_SET:
                response.set_error(
                    "empty request: set one of status, watch_events, set_master_state, set_red_state, image_history, "
                    "switchover, force_standby");
                break;
        }
        send(response);
    }

    static void answer(Response& response, const std::optional<std::string>& error) {
        if (error) {
            response.set_error(*error);
        } else {
            response.set_ok(true);
        }
    }

    void reject(const std::string& why) {
        Response response;
        response.set_error(why);
        send(response);
        closing_ = true;
    }

    void write() {
        auto self = shared_from_this();
        asio::async_write(socket_, asio::buffer(outbox_.front()), [this, self](const boost::system::error_code& ec, std::size_t) {
            if (ec) return;
            outbox_.pop_front();
            if (!outbox_.empty()) {
                write();
            } else if (closing_) {
                boost::system::error_code ignored;
                socket_.shutdown(stream_protocol::socket::shutdown_both, ignored);
            }
        });
    }

    stream_protocol::socket socket_;
    ControlHandler& handler_;
    const std::deque<EventMessage>& backlog_;
    std::array<char, 4096> buffer_{};
    DelimitedReader reader_;
    std::deque<std::string> outbox_;
    bool watching_ = false;
    bool closing_ = false;
};

ControlServer::ControlServer(asio::io_context& io, ControlHandler& handler, SocketSettings settings)
    : io_(io), handler_(handler), settings_(std::move(settings)), acceptor_(io) {}

ControlServer::~ControlServer() {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    std::error_code fs_ignored;
    if (!settings_.path.empty()) std::filesystem::remove(settings_.path, fs_ignored);
}

Expected<void, std::string> ControlServer::open() {
    const std::filesystem::path path(settings_.path);
    std::error_code fs_error;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), fs_error);
    if (std::filesystem::exists(path)) {
        // A socket nobody answers on is left over from a crash: replace it.
        stream_protocol::socket probe(io_);
        boost::system::error_code connect_error;
        probe.connect(stream_protocol::endpoint(settings_.path), connect_error);
        if (!connect_error) return unexpected(fmt::format("{}: another daemon is listening there", settings_.path));
        std::filesystem::remove(path, fs_error);
    }
    boost::system::error_code ec;
    acceptor_.open(stream_protocol(), ec);
    if (!ec) acceptor_.bind(stream_protocol::endpoint(settings_.path), ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) return unexpected(fmt::format("{}: {}", settings_.path, ec.message()));
    if (::chmod(settings_.path.c_str(), settings_.mode) != 0) {
        return unexpected(fmt::format("{}: chmod {:o}: {}", settings_.path, settings_.mode, std::strerror(errno)));
    }
    if (!settings_.group.empty()) {
        const group* g = ::getgrnam(settings_.group.c_str());
        if (g == nullptr) return unexpected(fmt::format("control.group: no group named '{}'", settings_.group));
        if (::chown(settings_.path.c_str(), static_cast<uid_t>(-1), g->gr_gid) != 0) {
            return unexpected(fmt::format("{}: chown to group {}: {}", settings_.path, settings_.group, std::strerror(errno)));
        }
    }
    accept();
    logger("control")->info("operator socket {} (mode {:o})", settings_.path, settings_.mode);
    return {};
}

void ControlServer::accept() {
    acceptor_.async_accept([this](const boost::system::error_code& ec, stream_protocol::socket socket) {
        if (ec) return;  // closed
        auto session = std::make_shared<Session>(std::move(socket), handler_, backlog_);
        std::erase_if(sessions_, [](const std::weak_ptr<Session>& s) { return s.expired(); });
        sessions_.push_back(session);
        session->start();
        accept();
    });
}

void ControlServer::publish(const EventMessage& event) {
    backlog_.push_back(event);
    if (backlog_.size() > kBacklog) backlog_.pop_front();
    Response response;
    response.set_ok(true);
    *response.mutable_event() = event;
    for (const auto& weak : sessions_) {
        if (auto session = weak.lock(); session && session->watching()) session->send(response);
    }
}

std::size_t ControlServer::clients() const {
    return static_cast<std::size_t>(
        std::count_if(sessions_.begin(), sessions_.end(), [](const std::weak_ptr<Session>& s) { return !s.expired(); }));
}

}  // namespace ecpair::control
